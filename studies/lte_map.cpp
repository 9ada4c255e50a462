#include "studies/lte_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "core/body.hpp"
#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "studies/missing_value.hpp"
#include "studies/mpi/distribution.hpp"
#include "trajectory/accuracy_check.hpp"

namespace flexref::studies {
namespace {

/// Deflections δ(t) (body frame) and attitudes of one run.
struct Response {
  std::vector<Eigen::Vector3d> deflection;
  std::vector<rotation::EulerParameters> attitude;
};

Response integrate(const core::Model& model, int body_index, const core::TrackedPoint& point,
                   const std::vector<double>& times, const std::string& solver, double rtol) {
  reference::SolverOptions options;
  options.rtol = rtol;
  const core::Trajectory trajectory =
      reference::solve_reference(solver, model, times, options).trajectory;
  const core::Body& body = model.body(body_index);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(body.mode_count());
  const Eigen::Vector3d undeformed = body.p_BrP_B(point, zero);
  Response r;
  for (const core::State& state : trajectory.states) {
    const core::BodyState& s = state[static_cast<std::size_t>(body_index)];
    r.deflection.push_back(body.p_BrP_B(point, s.q_f) - undeformed);
    r.attitude.push_back(s.theta_WB);
  }
  return r;
}

double max_norm(const std::vector<Eigen::Vector3d>& v) {
  double m = 0.0;
  for (const Eigen::Vector3d& x : v) m = std::max(m, x.norm());
  return m;
}

/// max_t |a − b| / scale.
double max_difference(const Response& a, const Response& b, double scale) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.deflection.size(); ++i) {
    m = std::max(m, (a.deflection[i] - b.deflection[i]).norm());
  }
  return m / scale;
}

double max_angle(const Response& a, const Response& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.attitude.size(); ++i) {
    m = std::max(m, rotation::geodesic_angle(a.attitude[i], b.attitude[i]));
  }
  return m;
}

/// The deflection component that varies most in `truth` over the output indices [from, end).
int dominant_component(const Response& truth, std::size_t from) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (std::size_t i = from; i < truth.deflection.size(); ++i) {
    lo = lo.cwiseMin(truth.deflection[i]);
    hi = hi.cwiseMax(truth.deflection[i]);
  }
  Eigen::Index c = 0;
  (hi - lo).maxCoeff(&c);
  return static_cast<int>(c);
}

/// Dominant angular frequency of component c over [from, end): π (crossings − 1) / (time from
/// the first to the last crossing of the mean), crossings by linear interpolation; NaN with
/// fewer than 3 crossings.
double dominant_frequency(const Response& r, const std::vector<double>& times, std::size_t from,
                          int c) {
  double mean = 0.0;
  for (std::size_t i = from; i < times.size(); ++i) mean += r.deflection[i](c);
  mean /= static_cast<double>(times.size() - from);
  std::vector<double> crossings;
  for (std::size_t i = from + 1; i < times.size(); ++i) {
    const double a = r.deflection[i - 1](c) - mean;
    const double b = r.deflection[i](c) - mean;
    if ((a < 0.0) != (b < 0.0)) {
      crossings.push_back(times[i - 1] + (times[i] - times[i - 1]) * a / (a - b));
    }
  }
  if (crossings.size() < 3) return kNaN;
  return std::numbers::pi * static_cast<double>(crossings.size() - 1) /
         (crossings.back() - crossings.front());
}

/// Tip, envelope and frequency metrics of model m against the truth.
struct Metrics {
  double tip = kNaN, envelope = kNaN, frequency = kNaN;
};

Metrics compare(const Response& m, const Response& truth, double truth_peak, double truth_frequency,
                const std::vector<double>& times, std::size_t from, int component) {
  Metrics out;
  out.tip = max_difference(m, truth, truth_peak);
  out.envelope = max_norm(m.deflection) / truth_peak - 1.0;
  out.frequency = dominant_frequency(m, times, from, component) / truth_frequency - 1.0;
  return out;
}

/// Every field of a grid point, for distributed_for.
SlotCodec point_codec(std::vector<LteMapPoint>& points) {
  require_codec_size<LteMapPoint, 184>();
  const auto fields = [](auto& io, auto& p) {
    io(p.spin_ratio, p.inertia_ratio, p.spin, p.omega1, p.hub_scale, p.load_scale, p.tip_error,
       p.envelope_error, p.frequency_shift, p.attitude_error, p.classical_tip_error,
       p.classical_envelope_error, p.classical_frequency_shift, p.max_deflection, p.truth_frequency,
       p.truth_estimate, p.lte_estimate, p.classical_estimate, p.resolved, p.classical_resolved,
       p.status);
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

}  // namespace

LteMapBase lte_map_base(const core::Model& model, const LteMapOptions& options) {
  return lte_map_base(model, options.body, options.point);
}

LteMapResult run_lte_map(const LteModelFactory& factory, const LteMapOptions& options) {
  if (options.spin_ratios.empty() || options.inertia_ratios.empty()) {
    throw std::invalid_argument("lte-map: need at least one spin ratio and one inertia ratio");
  }
  if (!(options.rtol > 0.0) || !(options.estimate_factor > 1.0)) {
    throw std::invalid_argument("lte-map: need rtol > 0 and an estimate factor > 1");
  }
  trajectory::check_accuracy_check_rtol("lte-map", options.rtol, options.estimate_factor);
  LteMapResult result;
  result.options = options;
  const LteMapLevel truth_level =
      options.stiffened_truth ? LteMapLevel::kStiffened : LteMapLevel::kClassical;
  const core::Model scene_model = factory(truth_level, std::nullopt);
  result.base = lte_map_base(scene_model, options);
  const int body_index = lte_map_body(scene_model, options.body);
  const core::TrackedPoint point = lte_map_point(scene_model.body(body_index), result.base.point);
  const std::vector<double> times = core::output_times(options.end_time, options.output_step);
  // The frequency metric's window: the second half of the horizon.
  const auto second_half = static_cast<std::size_t>(
      std::lower_bound(times.begin(), times.end(), 0.5 * options.end_time) - times.begin());

  const std::size_t nx = options.spin_ratios.size();
  const std::size_t ny = options.inertia_ratios.size();
  std::vector<LteMapScaling> scalings;
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i < nx; ++i) {
      scalings.push_back(lte_map_scaling(result.base, options.spin_ratios[i],
                                         options.inertia_ratios[j], options.scale_loads));
    }
  }
  const int n = static_cast<int>(scalings.size());
  result.points.resize(scalings.size());
  ProgressLine progress("lte-map", "grid points", options.progress);
  const auto task = [&](int k) {
    const auto uk = static_cast<std::size_t>(k);
    LteMapPoint& out = result.points[uk];
    out.spin_ratio = options.spin_ratios[uk % nx];
    out.inertia_ratio = options.inertia_ratios[uk / nx];
    out.omega1 = result.base.omega1;
    out.spin = out.spin_ratio * out.omega1;
    out.hub_scale = scalings[uk].hub_scale;
    out.load_scale = scalings[uk].load_scale;
    try {
      // The accuracy check: the same run estimate_factor times tighter (accuracy_check_rtol).
      const double tight = trajectory::accuracy_check_rtol(options.rtol, options.estimate_factor);
      const auto run = [&](LteMapLevel level, double rtol) {
        return integrate(factory(level, scalings[uk]), body_index, point, times, options.solver,
                         rtol);
      };
      const Response t = run(truth_level, options.rtol);
      const Response l = run(LteMapLevel::kLte, options.rtol);
      out.max_deflection = max_norm(t.deflection);
      if (!(out.max_deflection > 0.0)) {
        throw std::runtime_error("the truth's tracked point does not deflect");
      }
      const int c = dominant_component(t, second_half);
      out.truth_frequency = dominant_frequency(t, times, second_half, c);
      const Metrics lte =
          compare(l, t, out.max_deflection, out.truth_frequency, times, second_half, c);
      out.tip_error = lte.tip;
      out.envelope_error = lte.envelope;
      out.frequency_shift = lte.frequency;
      out.attitude_error = max_angle(l, t);
      out.truth_estimate = max_difference(run(truth_level, tight), t, out.max_deflection);
      out.lte_estimate = max_difference(run(LteMapLevel::kLte, tight), l, out.max_deflection);
      out.resolved = out.tip_error >= 100.0 * std::max(out.truth_estimate, out.lte_estimate);
      out.classical_tip_error = kNaN;
      out.classical_envelope_error = kNaN;
      out.classical_frequency_shift = kNaN;
      out.classical_estimate = kNaN;
      if (options.stiffened_truth) {
        const Response coupled = run(LteMapLevel::kClassical, options.rtol);
        const Metrics classical =
            compare(coupled, t, out.max_deflection, out.truth_frequency, times, second_half, c);
        out.classical_tip_error = classical.tip;
        out.classical_envelope_error = classical.envelope;
        out.classical_frequency_shift = classical.frequency;
        out.classical_estimate =
            max_difference(run(LteMapLevel::kClassical, tight), coupled, out.max_deflection);
        out.classical_resolved =
            out.classical_tip_error >= 100.0 * std::max(out.truth_estimate, out.classical_estimate);
      }
      // A deflection without three mean crossings over the second half has no dominant
      // frequency: the row says so instead of carrying a NaN.
      const char* without = std::isnan(out.truth_frequency)   ? "the truth's"
                            : std::isnan(out.frequency_shift) ? "the LTE model's"
                            : options.stiffened_truth && std::isnan(out.classical_frequency_shift)
                                ? "the classical model's"
                                : nullptr;
      if (without != nullptr) {
        out.status = std::string("no frequency shift: ") + without +
                     " deflection crosses its mean fewer than 3 times over the second half";
      }
    } catch (const std::exception& e) {
      out.tip_error = kNaN;
      out.attitude_error = kNaN;
      out.status = std::string("failed: ") + e.what();
    }
  };
  distributed_for(n, options.jobs, task, point_codec(result.points), progress.callback());
  progress.finish();

  int unresolved = 0;
  int failed = 0;
  int no_frequency = 0;
  for (const LteMapPoint& p : result.points) {
    if (p.status.starts_with("failed")) {
      ++failed;
    } else if (!p.resolved) {
      ++unresolved;
    }
    no_frequency += p.status.starts_with("no frequency") ? 1 : 0;
  }
  if (no_frequency > 0) {
    result.notes.push_back(std::to_string(no_frequency) +
                           " grid point(s) have no frequency shift (status in lte_map.csv): a "
                           "deflection crosses its mean fewer than 3 times over the second half");
  }
  if (unresolved > 0) {
    result.notes.push_back(std::to_string(unresolved) +
                           " grid point(s) marked '*' have an LTE error below 100x the "
                           "estimated error of a reference: the value is an upper bound, not a "
                           "measurement (tighten --rtol)");
  }
  int classical_unresolved = 0;
  for (const LteMapPoint& p : result.points) {
    if (options.stiffened_truth && !p.status.starts_with("failed") && !p.classical_resolved) {
      ++classical_unresolved;
    }
  }
  if (classical_unresolved > 0) {
    result.notes.push_back(std::to_string(classical_unresolved) +
                           " classical-model value(s) marked '*' are below 100x the estimated "
                           "error of a reference (upper bounds)");
  }
  if (!options.stiffened_truth) {
    result.notes.push_back(
        "truth = the classical coupled model (--truth coupled): it has no geometric stiffening "
        "and softens in the plane of rotation, so the map measures LTE against a model that is "
        "itself wrong at large spin (docs/lte_map.md)");
  }
  if (failed > 0) {
    result.notes.push_back(std::to_string(failed) +
                           " grid point(s) failed (status in lte_map.csv); shown as '-'");
  }
  return result;
}

}  // namespace flexref::studies
