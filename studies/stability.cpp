#include "studies/stability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/body.hpp"
#include "core/force_element.hpp"
#include "core/invariants.hpp"
#include "lie/method_registry.hpp"
#include "lie/stepper.hpp"
#include "studies/mpi/distribution.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Scan range of every bisection of the study, in h|W0|: from 1e-3 up to 1000.
constexpr double kLowStepTimesSpin = 1e-3;
constexpr double kCapStepTimesSpin = 1000.0;
/// Rotation per step of the "near π" run of the degenerate set.
constexpr double kNearPiStepTimesSpin = 3.1;

bool is_finite(const core::State& state) {
  for (const core::BodyState& b : state) {
    if (!b.p_WBr.allFinite() || !b.theta_WB.allFinite() || !b.v_WBr.allFinite() ||
        !b.w_WB_B.allFinite()) {
      return false;
    }
  }
  return true;
}

void require_torque_free(const core::Model& model) {
  if (!model.elements().empty()) {
    throw std::invalid_argument(
        "stability: the energy and momentum criteria need a torque-free model (no force "
        "elements)");
  }
}

std::string format_double(double x, int precision = 4) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", precision, x);
  return buffer;
}

std::string csv_double(double x) { return format_double(x, 17); }

/// One bisection on the free body (I, w0); classification of the unstable end.
StabilityPoint bisect_point(const std::string& scheme, const lie::MethodOptions& method_options,
                            const Eigen::Matrix3d& I_Bcm_B, const Eigen::Vector3d& w_WB_B,
                            const StabilityCriterion& criterion, double relative_tolerance) {
  const core::Model model = make_free_body_model(I_Bcm_B, w_WB_B);
  const double spin = w_WB_B.norm();
  const StableStepBracket bracket = bisect_largest_stable(
      [&](double h) {
        return classify_run(model, scheme, method_options, h, criterion) == "stable";
      },
      kLowStepTimesSpin / spin, kCapStepTimesSpin / spin, relative_tolerance);
  StabilityPoint point;
  point.scheme = scheme;
  point.spin = spin;
  point.h_max = bracket.h_stable;
  point.h_unstable = bracket.h_unstable;
  point.classification =
      std::isfinite(bracket.h_unstable)
          ? classify_run(model, scheme, method_options, bracket.h_unstable, criterion)
          : "stable to cap";
  return point;
}

/// Long run of one scheme: samples hold the maximum drifts over the steps since the previous
/// sample, so oscillating errors are not aliased away.
SlotCodec point_codec(std::vector<StabilityPoint>& points) {
  require_codec_size<StabilityPoint, 160>();
  const auto fields = [](auto& io, auto& p) {
    io(p.scheme, p.parameter, p.value, p.spin, p.h_max, p.h_unstable, p.classification, p.near_pi);
  };
  return {[&points, fields](int i, SlotWriter& w) {
            auto put = [&w](const auto&... x) { (w.put(x), ...); };
            fields(put, points[static_cast<std::size_t>(i)]);
          },
          [&points, fields](int i, SlotReader& r) {
            auto get = [&r](auto&... x) { (r.get(x), ...); };
            fields(get, points[static_cast<std::size_t>(i)]);
          }};
}

SlotCodec long_run_codec(std::vector<std::vector<LongRunSample>>& runs) {
  require_codec_size<LongRunSample, 104>();
  const auto fields = [](auto& io, auto& s) {
    io(s.scheme, s.step, s.t, s.energy_drift, s.momentum_drift, s.quaternion_drift, s.status);
  };
  return {[&runs, fields](int i, SlotWriter& w) {
            auto put = [&w](const auto&... x) { (w.put(x), ...); };
            const auto& run = runs[static_cast<std::size_t>(i)];
            w.put_int(static_cast<std::int64_t>(run.size()));
            for (const LongRunSample& s : run) fields(put, s);
          },
          [&runs, fields](int i, SlotReader& r) {
            auto get = [&r](auto&... x) { (r.get(x), ...); };
            auto& run = runs[static_cast<std::size_t>(i)];
            run.resize(static_cast<std::size_t>(r.get_int()));
            for (LongRunSample& s : run) fields(get, s);
          }};
}

std::vector<LongRunSample> long_run(const std::string& scheme, const StabilityOptions& options) {
  const core::Model model = make_free_body_model(options.I_Bcm_B, options.w_direction_B);
  const std::unique_ptr<lie::Stepper> stepper =
      lie::make_stepper(scheme, model, options.method_options);
  const core::State s0 = model.initial_state();
  stepper->initialize(0.0, s0);
  const double E0 = model.kinetic_energy(s0);
  const Eigen::Vector3d pi0 = model.angular_momentum_W(s0);
  const long n = options.long_run_steps;
  const long samples = std::max(1L, std::min<long>(options.long_run_samples, n));
  std::vector<LongRunSample> out;
  LongRunSample current;
  current.scheme = scheme;
  current.status = "ok";
  long next_sample = (n + samples - 1) / samples;  // ⌈n/samples⌉
  long sample_index = 1;
  for (long k = 1; k <= n; ++k) {
    std::string failure;
    try {
      const lie::StepStatus status = stepper->step(options.long_run_h);
      if (!status.ok) failure = "newton failure: " + status.message;
    } catch (const std::exception& e) {
      failure = std::string("exception: ") + e.what();
    }
    const core::State& s = stepper->state();
    if (failure.empty() && !is_finite(s)) failure = "non-finite";
    if (failure.empty()) {
      const double q = s[0].theta_WB.norm();
      current.energy_drift =
          std::max(current.energy_drift, std::abs(model.kinetic_energy(s) - E0) / std::abs(E0));
      current.momentum_drift =
          std::max(current.momentum_drift, (model.angular_momentum_W(s) - pi0).norm() / pi0.norm());
      current.quaternion_drift = std::max(current.quaternion_drift, std::abs(q - 1.0));
    }
    // Both drifts are of invariants of the torque-free body: beyond the invariant monitor's
    // tolerance (core/invariants.hpp) the run is unstable from here on.
    if (failure.empty() && current.status == "ok" &&
        (current.energy_drift > core::kInvariantTolerance ||
         current.momentum_drift > core::kInvariantTolerance)) {
      current.status = "unstable";
    }
    if (k == next_sample || k == n || !failure.empty()) {
      current.step = k;
      current.t = static_cast<double>(k) * options.long_run_h;
      if (!failure.empty()) current.status = failure;
      out.push_back(current);
      if (!failure.empty()) break;
      current.energy_drift = current.momentum_drift = current.quaternion_drift = 0.0;
      ++sample_index;
      // Samples at k = ⌈n·i/samples⌉, i = 1 … samples.
      next_sample = (n * sample_index + samples - 1) / samples;
    }
  }
  return out;
}

}  // namespace

bool StableStepBracket::bracketed() const { return h_stable > 0.0 && std::isfinite(h_unstable); }

StableStepBracket bisect_largest_stable(const std::function<bool(double h)>& is_stable, double h_lo,
                                        double h_cap, double relative_tolerance,
                                        double scan_ratio) {
  if (!(h_lo > 0.0) || !(h_cap > h_lo) || !(relative_tolerance > 0.0) || !(scan_ratio > 1.0)) {
    throw std::invalid_argument(
        "bisect_largest_stable: need 0 < h_lo < h_cap, relative_tolerance > 0, scan_ratio > 1");
  }
  StableStepBracket bracket;
  bracket.h_unstable = kInfinity;
  const auto test = [&](double h) {
    ++bracket.evaluations;
    return is_stable(h);
  };
  double lo = h_lo;
  double hi = h_lo;
  if (!test(lo)) {
    // Shrink the stable end: h_lo/4, h_lo/16, … (at most 10 times).
    int shrinks = 0;
    do {
      hi = lo;
      if (++shrinks > 10) {
        bracket.h_unstable = hi;
        return bracket;
      }
      lo /= 4.0;
    } while (!test(lo));
  } else {
    // Scan upward h_lo·rᵏ to the first unstable step or h_cap: stability need not be monotone
    // in h (a scheme can be stable again beyond an unstable window: docs/design/studies.md,
    // "Stability at the extremes"), and a coarse bracket could step over the window.
    for (;;) {
      hi = std::min(lo * scan_ratio, h_cap);
      if (!test(hi)) break;
      lo = hi;
      if (hi >= h_cap) {
        bracket.h_stable = lo;
        return bracket;
      }
    }
  }
  // Invariant: lo stable, hi unstable. Bisect on log h (geometric midpoint).
  while (hi / lo > 1.0 + relative_tolerance) {
    const double mid = std::sqrt(lo * hi);
    if (test(mid)) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  bracket.h_stable = lo;
  bracket.h_unstable = hi;
  return bracket;
}

std::string classify_run(const core::Model& model, const std::string& scheme,
                         const lie::MethodOptions& method_options, double h,
                         const StabilityCriterion& criterion) {
  require_torque_free(model);
  const std::unique_ptr<lie::Stepper> stepper = lie::make_stepper(scheme, model, method_options);
  try {
    const core::State s0 = model.initial_state();
    stepper->initialize(0.0, s0);
    const double E0 = model.kinetic_energy(s0);
    const Eigen::Vector3d pi0 = model.angular_momentum_W(s0);
    for (long k = 0; k < criterion.steps; ++k) {
      const lie::StepStatus status = stepper->step(h);
      if (!status.ok) return "newton failure: " + status.message;
      const core::State& s = stepper->state();
      if (!is_finite(s)) return "non-finite";
      const double E = model.kinetic_energy(s);
      const Eigen::Vector3d pi = model.angular_momentum_W(s);
      if (!std::isfinite(E) || !pi.allFinite()) return "non-finite";
      if (std::abs(E - E0) > criterion.energy_factor * std::abs(E0)) return "energy growth";
      if ((pi - pi0).norm() > criterion.momentum_factor * pi0.norm()) return "momentum growth";
    }
  } catch (const std::exception& e) {
    return std::string("exception: ") + e.what();
  }
  return "stable";
}

double largest_stable_step(const core::Model& model, const std::string& scheme,
                           const lie::MethodOptions& method_options,
                           const StabilityCriterion& criterion, double h_lo, double h_cap,
                           double relative_tolerance) {
  require_torque_free(model);
  return bisect_largest_stable(
             [&](double h) {
               return classify_run(model, scheme, method_options, h, criterion) == "stable";
             },
             h_lo, h_cap, relative_tolerance)
      .h_stable;
}

core::Model make_free_body_model(const Eigen::Matrix3d& I_Bcm_B, const Eigen::Vector3d& w_WB_B) {
  core::RigidBodyDescription description;
  description.name = "body";
  description.mass = 1.0;
  description.I_Bcm_B = I_Bcm_B;
  description.initial.w_WB_B = w_WB_B;
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(description));
  return core::Model(std::move(bodies), {});
}

Eigen::Matrix3d rod_inertia(double ratio) {
  if (!(ratio >= 1.0)) throw std::invalid_argument("rod_inertia: need J3/J1 >= 1");
  return Eigen::Vector3d(1.0, ratio - 0.5, ratio).asDiagonal();
}

std::vector<std::pair<std::string, Eigen::Matrix3d>> degenerate_bodies() {
  return {
      {"flat disk J=(1,1,2)", Eigen::Vector3d(1.0, 1.0, 2.0).asDiagonal()},
      {"flat plate J=(1,2,3)", Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal()},
      {"rod J3/J1=1e2", rod_inertia(1e2)},
      {"rod J3/J1=1e4", rod_inertia(1e4)},
      {"rod J3/J1=1e6", rod_inertia(1e6)},
  };
}

StabilityResult run_stability(const StabilityOptions& options) {
  if (options.parameter != StabilityParameter::kSpin &&
      options.parameter != StabilityParameter::kInertiaRatio) {
    throw std::invalid_argument(
        std::string("stability: parameter must be 'spin' or 'inertia_ratio', not '") +
        to_string(options.parameter) + "'");
  }
  if (!(options.w_direction_B.norm() > 0.0) || !(options.spin > 0.0)) {
    throw std::invalid_argument("stability: the initial angular velocity must be non-zero");
  }
  const std::vector<std::string> known = lie::scheme_names();
  for (const std::string& scheme : options.schemes) {
    if (std::find(known.begin(), known.end(), scheme) == known.end()) {
      throw std::invalid_argument("stability: unknown scheme '" + scheme + "'");
    }
  }
  // Refusals before any run: an option no scheme reads, a value a scheme's factory refuses.
  lie::check_method_options(options.method_options, options.schemes);
  const core::Model base = make_free_body_model(options.I_Bcm_B, options.w_direction_B);
  for (const std::string& scheme : options.schemes) {
    (void)lie::make_stepper(scheme, base, options.method_options);
  }
  StabilityResult result;
  result.options = options;
  const Eigen::Vector3d direction = options.w_direction_B.normalized();
  const auto n_schemes = static_cast<int>(options.schemes.size());
  const auto scheme_of = [&](int task) {
    return options.schemes[static_cast<std::size_t>(task % n_schemes)];
  };

  // Sweep: task = value index × schemes + scheme index; each task writes its own slot.
  const auto n_values = static_cast<int>(options.values.size());
  const int n_total =
      n_values * n_schemes +
      (options.degenerate ? static_cast<int>(degenerate_bodies().size()) : 0) * n_schemes +
      (options.long_run_steps > 0 ? n_schemes : 0);
  ProgressLine progress("stability", "runs", options.progress);
  int offset = 0;
  result.sweep.resize(options.values.size() * options.schemes.size());
  distributed_for(
      n_values * n_schemes, options.jobs,
      [&](int task) {
        const double value = options.values[static_cast<std::size_t>(task / n_schemes)];
        StabilityPoint point =
            options.parameter == StabilityParameter::kSpin
                ? bisect_point(scheme_of(task), options.method_options, options.I_Bcm_B,
                               value * direction, options.criterion, options.relative_tolerance)
                : bisect_point(scheme_of(task), options.method_options, rod_inertia(value),
                               options.spin * direction, options.criterion,
                               options.relative_tolerance);
        point.parameter = to_string(options.parameter);
        point.value = value;
        result.sweep[static_cast<std::size_t>(task)] = std::move(point);
      },
      point_codec(result.sweep), progress.callback(offset, n_total));
  offset += n_values * n_schemes;

  if (options.degenerate) {
    const auto bodies = degenerate_bodies();
    const auto n_bodies = static_cast<int>(bodies.size());
    result.degenerate.resize(bodies.size() * options.schemes.size());
    distributed_for(
        n_bodies * n_schemes, options.jobs,
        [&](int task) {
          const auto& [name, inertia] = bodies[static_cast<std::size_t>(task / n_schemes)];
          const Eigen::Vector3d w = options.spin * direction;
          StabilityPoint point = bisect_point(scheme_of(task), options.method_options, inertia, w,
                                              options.criterion, options.relative_tolerance);
          point.parameter = name;
          point.value = inertia(2, 2) / inertia(0, 0);
          point.near_pi = classify_run(make_free_body_model(inertia, w), scheme_of(task),
                                       options.method_options, kNearPiStepTimesSpin / options.spin,
                                       options.criterion);
          result.degenerate[static_cast<std::size_t>(task)] = std::move(point);
        },
        point_codec(result.degenerate), progress.callback(offset, n_total));
    offset += n_bodies * n_schemes;
  }

  if (options.long_run_steps > 0) {
    std::vector<std::vector<LongRunSample>> runs(options.schemes.size());
    distributed_for(
        n_schemes, options.jobs,
        [&](int i) { runs[static_cast<std::size_t>(i)] = long_run(scheme_of(i), options); },
        long_run_codec(runs), progress.callback(offset, n_total));
    for (auto& run : runs) result.long_run.insert(result.long_run.end(), run.begin(), run.end());
  }
  progress.finish();
  return result;
}

std::string stability_csv(const StabilityResult& result) {
  std::ostringstream out;
  out << "scheme,parameter,value,h_max,h_max_times_spin,classification\n";
  for (const auto* points : {&result.sweep, &result.degenerate}) {
    for (const StabilityPoint& p : *points) {
      out << p.scheme << ',' << trajectory::csv_text(p.parameter) << ',' << csv_double(p.value)
          << ',' << csv_double(p.h_max) << ',' << csv_double(p.h_max * p.spin) << ','
          << trajectory::csv_text(p.classification) << '\n';
    }
  }
  return out.str();
}

std::string long_run_csv(const StabilityResult& result) {
  std::ostringstream out;
  out << "scheme,step,t,energy_drift,momentum_drift,quaternion_norm_drift,status\n";
  for (const LongRunSample& s : result.long_run) {
    out << s.scheme << ',' << s.step << ',' << csv_double(s.t) << ',' << csv_double(s.energy_drift)
        << ',' << csv_double(s.momentum_drift) << ',' << csv_double(s.quaternion_drift) << ','
        << trajectory::csv_text(s.status) << '\n';
  }
  return out.str();
}

std::string format_stability_table(const StabilityResult& result) {
  const StabilityOptions& o = result.options;
  std::ostringstream out;
  out << "largest stable step (" << o.criterion.steps << " steps; unstable: non-finite, Newton "
      << "failure, |dE| > " << o.criterion.energy_factor << "|E0| or |dpi| > "
      << o.criterion.momentum_factor << "|pi0|)\n";
  char line[512];
  std::snprintf(line, sizeof line, "%-6s %-24s %12s %10s %12s %12s  %s\n", "scheme",
                o.parameter == StabilityParameter::kSpin ? "|W0| [rad/s]" : "J3/J1", "value",
                "|W0|", "h_max [s]", "h_max*|W0|", "unstable above because");
  out << line;
  const auto print = [&](const StabilityPoint& p, bool with_near_pi) {
    std::snprintf(line, sizeof line, "%-6s %-24s %12.4g %10.4g %12.4g %12.4g  ", p.scheme.c_str(),
                  p.parameter.c_str(), p.value, p.spin, p.h_max, p.h_max * p.spin);
    out << line << p.classification;
    if (with_near_pi) out << "; at h|W0|=3.1: " << p.near_pi;
    out << '\n';
  };
  for (const StabilityPoint& p : result.sweep) print(p, false);
  if (!result.degenerate.empty()) {
    out << "\ndegenerate and extreme bodies (|W0| = " << o.spin << " rad/s)\n";
    for (const StabilityPoint& p : result.degenerate) print(p, true);
  }
  if (!result.long_run.empty()) {
    out << "\nlong run: " << o.long_run_steps << " steps of h = " << o.long_run_h
        << " s, max drifts\n";
    std::snprintf(line, sizeof line, "%-6s %14s %14s %14s  %s\n", "scheme", "|dE|/E0",
                  "|dpi|/|pi0|", "||q|-1|", "status");
    out << line;
    for (const std::string& scheme : o.schemes) {
      LongRunSample worst;
      worst.status = "ok";
      std::string previous = "ok";
      for (const LongRunSample& s : result.long_run) {
        if (s.scheme != scheme) continue;
        worst.energy_drift = std::max(worst.energy_drift, s.energy_drift);
        worst.momentum_drift = std::max(worst.momentum_drift, s.momentum_drift);
        worst.quaternion_drift = std::max(worst.quaternion_drift, s.quaternion_drift);
        // Where a status first appears ("unstable" holds for every later sample).
        if (s.status != previous) worst.status = s.status + " from step " + std::to_string(s.step);
        previous = s.status;
      }
      std::snprintf(line, sizeof line, "%-6s %14.3e %14.3e %14.3e  ", scheme.c_str(),
                    worst.energy_drift, worst.momentum_drift, worst.quaternion_drift);
      out << line << worst.status << '\n';
    }
  }
  return out.str();
}

}  // namespace flexref::studies
