#include "studies/lte_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/body.hpp"
#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/build_model.hpp"
#include "studies/missing_value.hpp"
#include "studies/mpi/distribution.hpp"
#include "trajectory/accuracy_check.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {
namespace {

int find_flexible_body(const core::Model& model, int requested) {
  if (requested >= 0) {
    if (requested >= model.num_bodies() || !model.body(requested).is_flexible() ||
        !model.body(requested).is_free()) {
      throw std::invalid_argument("lte-map: body " + std::to_string(requested) +
                                  " is not a free flexible body");
    }
    return requested;
  }
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (model.body(i).is_flexible() && model.body(i).is_free()) return i;
  }
  throw std::invalid_argument(
      "lte-map: the scene has no free flexible body (the map needs a free hub carrying a "
      "flexible part, e.g. scenes/flexible_spinner.toml)");
}

const core::TrackedPoint& find_deforming_point(const core::Body& body, const std::string& name) {
  const core::TrackedPoint* best = nullptr;
  double best_distance = -1.0;
  for (const core::TrackedPoint& p : body.description().points) {
    if (!name.empty()) {
      if (p.name == name) {
        if (p.node < 0) {
          throw std::invalid_argument("lte-map: point '" + name + "' of body '" + body.name() +
                                      "' is not a node of the flexible part (it does not deform)");
        }
        return p;
      }
      continue;
    }
    if (p.node < 0) continue;
    const double distance = body.p_BrP_B(p.p_BoP_B).norm();
    if (distance > best_distance) {
      best = &p;
      best_distance = distance;
    }
  }
  if (!name.empty()) {
    throw std::invalid_argument("lte-map: body '" + body.name() + "' has no point '" + name + "'");
  }
  if (best == nullptr) {
    throw std::invalid_argument("lte-map: body '" + body.name() +
                                "' tracks no node point (add one, e.g. { name = \"tip\", node = "
                                "\"node10\" }): the metric is a node's deflection");
  }
  return *best;
}

/// m |(c − r)⊥|²: the parallel-axis term of a mass m at c about the axis u through r.
double offset_inertia(double m, const Eigen::Vector3d& c, const Eigen::Vector3d& r,
                      const Eigen::Vector3d& u) {
  const Eigen::Vector3d d = c - r;
  return m * (d - d.dot(u) * u).squaredNorm();
}

/// I_flex and I_rigid about the axis through the undeformed centre of mass for hub scale s.
std::pair<double, double> axis_inertias(const LteMapBase& b, double s) {
  const double m_hub = s * b.hub_mass;
  const Eigen::Vector3d p_BoBr_B =
      (b.flex_mass * b.p_BoFlex_B + m_hub * b.p_BoHub_B) / (b.flex_mass + m_hub);
  const double flex =
      b.flex_inertia + offset_inertia(b.flex_mass, b.p_BoFlex_B, p_BoBr_B, b.axis_B);
  const double rigid = s * b.hub_inertia + offset_inertia(m_hub, b.p_BoHub_B, p_BoBr_B, b.axis_B);
  return {flex, rigid};
}

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

/// Sets a flexible body's geometric stiffening (see lte_map_factory).
void set_geometric_stiffening(scene::BodySpec& body, bool on) {
  if (body.beam) {
    if (body.beam->geometric_stiffening == on) return;
    if (on && body.beam->parameters.boundary != flexible::BeamBoundary::kClampedFree) {
      throw std::invalid_argument("lte-map: body '" + body.description.name +
                                  "': geometric stiffening needs a clamped-free beam (use "
                                  "--truth coupled)");
    }
    body.beam->geometric_stiffening = on;
    scene::regenerate_beam_modes(body);
    return;
  }
  std::optional<core::FlexiblePart>& part = body.description.flexible;
  if (!part) return;
  if (!on) {
    part->modal.geometric.reset();
  } else if (!part->modal.geometric) {
    throw std::invalid_argument("lte-map: body '" + body.description.name +
                                "' has no geometric-stiffness data (its modal-data file has no "
                                "[geometric_stiffness] section; docs/geometric_stiffening.md): "
                                "use --truth coupled");
  }
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

std::string percent(double x) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  s << std::setprecision(x < 0.1 ? 2 : 3) << 100.0 * x;
  return s.str();
}

}  // namespace

std::vector<double> log_spaced_values(double lo, double hi, int count) {
  if (!(lo > 0.0) || !(hi >= lo) || !std::isfinite(hi) || count < 1) {
    throw std::invalid_argument("need 0 < min <= max and count >= 1");
  }
  std::vector<double> values;
  for (int i = 0; i < count; ++i) {
    const double f = count == 1 ? 0.0 : static_cast<double>(i) / (count - 1);
    values.push_back(lo * std::pow(hi / lo, f));
  }
  return values;
}

LteMapBase lte_map_base(const core::Model& model, const LteMapOptions& options) {
  const int index = find_flexible_body(model, options.body);
  const core::Body& body = model.body(index);
  LteMapBase base;
  base.body = body.name();
  base.point = find_deforming_point(body, options.point).name;
  if (body.natural_frequencies().size() == 0 || !(body.natural_frequencies()(0) > 0.0)) {
    throw std::invalid_argument("lte-map: body '" + base.body + "' has no positive frequency");
  }
  base.omega1 = body.natural_frequencies()(0);
  const Eigen::Vector3d w0 = body.description().initial.w_WB_B;
  base.spin = w0.norm();
  if (!(base.spin > 0.0)) {
    throw std::invalid_argument("lte-map: body '" + base.body +
                                "' has no initial angular velocity: the spin axis is its "
                                "direction (set angular_velocity in the scene)");
  }
  base.axis_B = w0 / base.spin;
  const core::RigidBodyDescription& d = body.description();
  base.hub_mass = d.mass;
  base.p_BoHub_B = d.p_BoBcm_B;
  base.hub_inertia = base.axis_B.dot(d.I_Bcm_B * base.axis_B);
  base.flex_mass = body.mass() - d.mass;
  // Total centre (Br of a free body) = (m_flex c_flex + m_hub c_hub) / m.
  base.p_BoFlex_B = (body.mass() * body.p_BoBr_B() - d.mass * d.p_BoBcm_B) / base.flex_mass;
  const double total = base.axis_B.dot(body.I_Br_B() * base.axis_B);
  const double hub_about_Br =
      base.hub_inertia + offset_inertia(d.mass, d.p_BoBcm_B, body.p_BoBr_B(), base.axis_B);
  const double flex_about_Br = total - hub_about_Br;
  base.flex_inertia =
      flex_about_Br - offset_inertia(base.flex_mass, base.p_BoFlex_B, body.p_BoBr_B(), base.axis_B);
  if (!(base.hub_mass > 0.0) || !(base.hub_inertia > 0.0) || !(base.flex_mass > 0.0) ||
      !(flex_about_Br > 0.0)) {
    throw std::invalid_argument("lte-map: body '" + base.body +
                                "' needs a hub with mass and inertia about the spin axis, and a "
                                "flexible part with inertia about it (the inertia ratio scales "
                                "the hub)");
  }
  base.inertia_flex = flex_about_Br;
  base.inertia_rigid = hub_about_Br;
  base.inertia_ratio = base.inertia_flex / base.inertia_rigid;
  base.spin_ratio = base.spin / base.omega1;
  return base;
}

double lte_map_inertia_ratio(const LteMapBase& base, double hub_scale) {
  const auto [flex, rigid] = axis_inertias(base, hub_scale);
  return flex / rigid;
}

LteMapScaling lte_map_scaling(const LteMapBase& base, double spin_ratio, double inertia_ratio,
                              bool scale_loads) {
  if (!(spin_ratio > 0.0) || !(inertia_ratio > 0.0) || !std::isfinite(spin_ratio) ||
      !std::isfinite(inertia_ratio)) {
    throw std::invalid_argument("lte-map: spin and inertia ratios must be positive and finite");
  }
  // y(s) decreases from +∞ (no hub) as the hub grows: bisection on log s.
  double lo = 1e-12;
  double hi = 1e12;
  if (!(lte_map_inertia_ratio(base, lo) > inertia_ratio) ||
      !(lte_map_inertia_ratio(base, hi) < inertia_ratio)) {
    std::ostringstream msg;
    msg << "lte-map: inertia ratio " << inertia_ratio
        << " cannot be reached by scaling the hub by a factor in [1e-12, 1e12]";
    throw std::invalid_argument(msg.str());
  }
  for (int i = 0; i < 200 && hi / lo > 1.0 + 1e-14; ++i) {
    const double mid = std::sqrt(lo * hi);
    (lte_map_inertia_ratio(base, mid) > inertia_ratio ? lo : hi) = mid;
  }
  const double s = std::sqrt(lo * hi);
  LteMapScaling scaling;
  scaling.hub_scale = s;
  scaling.w0_WB_B = spin_ratio * base.omega1 * base.axis_B;
  const double total_scene = base.inertia_flex + base.inertia_rigid;
  const auto [flex, rigid] = axis_inertias(base, s);
  const double total = flex + rigid;
  scaling.load_scale =
      scale_loads ? (spin_ratio * base.omega1 / base.spin) * (total / total_scene) : 1.0;
  return scaling;
}

LteModelFactory lte_map_factory(scene::SceneSpec spec, int body) {
  if (body < 0 || static_cast<std::size_t>(body) >= spec.bodies.size()) {
    throw std::invalid_argument("lte-map: no body " + std::to_string(body) + " in the scene");
  }
  return [spec = std::move(spec), body](LteMapLevel level,
                                        const std::optional<LteMapScaling>& scaling) {
    const core::FlexibleFormulation formulation = level == LteMapLevel::kLte
                                                      ? core::FlexibleFormulation::kLte
                                                      : core::FlexibleFormulation::kCoupled;
    scene::SceneSpec edited = spec;
    set_geometric_stiffening(edited.bodies[static_cast<std::size_t>(body)],
                             level == LteMapLevel::kStiffened);
    if (!scaling) return scene::build_model(edited, formulation);
    core::RigidBodyDescription& d = edited.bodies[static_cast<std::size_t>(body)].description;
    d.mass *= scaling->hub_scale;
    d.I_Bcm_B *= scaling->hub_scale;
    d.initial.w_WB_B = scaling->w0_WB_B;
    for (scene::LoadSpec& load : edited.loads) load.value *= scaling->load_scale;
    return scene::build_model(edited, formulation);
  };
}

bool lte_map_can_stiffen(const scene::SceneSpec& spec, int body) {
  if (body < 0 || static_cast<std::size_t>(body) >= spec.bodies.size()) return false;
  const scene::BodySpec& b = spec.bodies[static_cast<std::size_t>(body)];
  if (b.beam) return b.beam->parameters.boundary == flexible::BeamBoundary::kClampedFree;
  return b.description.flexible && b.description.flexible->modal.geometric.has_value();
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
  const int body_index = find_flexible_body(scene_model, options.body);
  const core::TrackedPoint point =
      find_deforming_point(scene_model.body(body_index), result.base.point);
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

double lte_map_value(const LteMapPoint& p, bool classical, LteMapMetric metric) {
  switch (metric) {
    case LteMapMetric::kTip:
      return std::abs(classical ? p.classical_tip_error : p.tip_error);
    case LteMapMetric::kEnvelope:
      return std::abs(classical ? p.classical_envelope_error : p.envelope_error);
    case LteMapMetric::kFrequency:
      return std::abs(classical ? p.classical_frequency_shift : p.frequency_shift);
  }
  return kNaN;
}

std::vector<double> lte_map_crossings(const LteMapResult& result, double level, bool classical,
                                      LteMapMetric metric) {
  const std::size_t nx = result.options.spin_ratios.size();
  const std::size_t ny = result.options.inertia_ratios.size();
  std::vector<double> crossings(ny, kNaN);
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const LteMapPoint& pa = result.points[j * nx + i];
      const LteMapPoint& pb = result.points[j * nx + i + 1];
      const double a = lte_map_value(pa, classical, metric);
      const double b = lte_map_value(pb, classical, metric);
      if (!(a > 0.0) || !(b > 0.0)) continue;
      if ((a - level) * (b - level) > 0.0 || a == b) continue;
      const double f = std::log(level / a) / std::log(b / a);
      crossings[j] = pa.spin_ratio * std::pow(pb.spin_ratio / pa.spin_ratio, f);
      break;
    }
  }
  return crossings;
}

std::string lte_map_csv(const LteMapResult& result) {
  std::ostringstream s;
  s.precision(17);
  s << "spin_ratio,inertia_ratio,spin,omega1,hub_scale,load_scale,tip_error,envelope_error,"
       "frequency_shift,attitude_error,classical_tip_error,classical_envelope_error,"
       "classical_frequency_shift,max_deflection,truth_frequency,truth_estimate,lte_estimate,"
       "classical_estimate,resolved,classical_resolved,status\n";
  for (const LteMapPoint& p : result.points) {
    const std::string status = trajectory::csv_text(p.status);
    const auto n = [](double x) { return trajectory::csv_number(x); };
    s << n(p.spin_ratio) << ',' << n(p.inertia_ratio) << ',' << n(p.spin) << ',' << n(p.omega1)
      << ',' << n(p.hub_scale) << ',' << n(p.load_scale) << ',' << n(p.tip_error) << ','
      << n(p.envelope_error) << ',' << n(p.frequency_shift) << ',' << n(p.attitude_error) << ','
      << n(p.classical_tip_error) << ',' << n(p.classical_envelope_error) << ','
      << n(p.classical_frequency_shift) << ',' << n(p.max_deflection) << ',' << n(p.truth_frequency)
      << ',' << n(p.truth_estimate) << ',' << n(p.lte_estimate) << ',' << n(p.classical_estimate)
      << ',' << (p.resolved ? 1 : 0) << ',' << (p.classical_resolved ? 1 : 0) << ',' << status
      << '\n';
  }
  return s.str();
}

namespace {

void grid_table(std::ostringstream& s, const LteMapResult& result, bool classical) {
  const std::size_t nx = result.options.spin_ratios.size();
  const std::size_t ny = result.options.inertia_ratios.size();
  s << std::setw(10) << "y \\ x";
  for (std::size_t i = 0; i < nx; ++i) {
    std::ostringstream h;
    h << std::setprecision(3) << result.options.spin_ratios[i];
    s << std::setw(9) << h.str();
  }
  s << "\n";
  for (std::size_t j = 0; j < ny; ++j) {
    std::ostringstream h;
    h << std::setprecision(3) << result.options.inertia_ratios[j];
    s << std::setw(10) << h.str();
    for (std::size_t i = 0; i < nx; ++i) {
      const LteMapPoint& p = result.points[j * nx + i];
      const bool resolved = classical ? p.classical_resolved : p.resolved;
      s << std::setw(9)
        << (percent(classical ? p.classical_tip_error : p.tip_error) +
            (!p.status.starts_with("failed") && !resolved ? "*" : ""));
    }
    s << "\n";
  }
}

void crossing_lines(std::ostringstream& s, const LteMapResult& result, bool classical) {
  const std::size_t ny = result.options.inertia_ratios.size();
  const std::pair<LteMapMetric, const char*> metrics[] = {
      {LteMapMetric::kTip, "L-inf tip error"},
      {LteMapMetric::kEnvelope, "peak deflection"},
      {LteMapMetric::kFrequency, "frequency shift"}};
  for (const auto& [metric, name] : metrics) {
    for (const double level : {0.01, 0.05, 0.20}) {
      const std::vector<double> c = lte_map_crossings(result, level, classical, metric);
      s << "  " << name << ", " << percent(level) << " % line at Omega0/omega1 =";
      for (std::size_t j = 0; j < ny; ++j) {
        std::ostringstream v;
        v << std::setprecision(3);
        if (std::isfinite(c[j])) {
          v << c[j];
        } else {
          v << "-";
        }
        s << (j ? ", " : " ") << v.str() << " (y=" << std::setprecision(3)
          << result.options.inertia_ratios[j] << std::setprecision(4) << ")";
      }
      s << "\n";
    }
  }
}

}  // namespace

std::string format_lte_map_table(const LteMapResult& result) {
  const LteMapBase& b = result.base;
  const bool stiffened = result.options.stiffened_truth;
  std::ostringstream s;
  s << std::setprecision(4);
  s << "body '" << b.body << "', point '" << b.point << "': omega1 = " << b.omega1
    << " rad/s, scene Omega0/omega1 = " << b.spin_ratio
    << ", scene I_flex/I_rigid = " << b.inertia_ratio << "\n";
  const std::string truth =
      stiffened ? "the coupled model with geometric stiffening" : "the classical coupled model";
  s << "truth: " << truth << "; metrics over the horizon [0, " << result.options.end_time
    << "] s (frequency: its second half)\n";
  s << "LTE L-inf tip-deflection error relative to the truth, % (rows: I_flex/I_rigid, "
       "columns: Omega0/omega1; * = below 100x the reference error estimate)\n";
  grid_table(s, result, false);
  if (stiffened) {
    s << "classical coupled model (no stiffening): L-inf tip-deflection error relative to the "
         "truth, %\n";
    grid_table(s, result, true);
  }
  s << "where LTE holds:\n";
  crossing_lines(s, result, false);
  if (stiffened) {
    s << "where the classical coupled model holds:\n";
    crossing_lines(s, result, true);
  }
  for (const std::string& note : result.notes) s << "note: " << note << "\n";
  return s.str();
}

}  // namespace flexref::studies
