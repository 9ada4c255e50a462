#include "studies/lte_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/body.hpp"
#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/build_model.hpp"
#include "studies/distribution.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::studies {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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

const core::TrackedPoint& find_point(const core::Body& body, const std::string& name) {
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

/// Every field of a grid point, for distributed_for.
SlotCodec point_codec(std::vector<LteMapPoint>& points) {
  require_codec_size<LteMapPoint, 128>();
  const auto fields = [](auto& io, auto& p) {
    io(p.spin_ratio, p.inertia_ratio, p.spin, p.omega1, p.hub_scale, p.load_scale, p.tip_error,
       p.attitude_error, p.max_deflection, p.coupled_estimate, p.lte_estimate, p.resolved,
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
  base.point = find_point(body, options.point).name;
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
  return [spec = std::move(spec), body](core::FlexibleFormulation formulation,
                                        const std::optional<LteMapScaling>& scaling) {
    if (!scaling) return scene::build_model(spec, formulation);
    scene::SceneSpec edited = spec;
    core::RigidBodyDescription& d = edited.bodies[static_cast<std::size_t>(body)].description;
    d.mass *= scaling->hub_scale;
    d.I_Bcm_B *= scaling->hub_scale;
    d.initial.w_WB_B = scaling->w0_WB_B;
    for (scene::LoadSpec& load : edited.loads) load.value *= scaling->load_scale;
    return scene::build_model(edited, formulation);
  };
}

LteMapResult run_lte_map(const LteModelFactory& factory, const LteMapOptions& options) {
  if (options.spin_ratios.empty() || options.inertia_ratios.empty()) {
    throw std::invalid_argument("lte-map: need at least one spin ratio and one inertia ratio");
  }
  if (!(options.rtol > 0.0) || !(options.estimate_factor > 1.0)) {
    throw std::invalid_argument("lte-map: need rtol > 0 and an estimate factor > 1");
  }
  LteMapResult result;
  result.options = options;
  const core::Model scene_model = factory(core::FlexibleFormulation::kCoupled, std::nullopt);
  result.base = lte_map_base(scene_model, options);
  const int body_index = find_flexible_body(scene_model, options.body);
  const core::TrackedPoint point = find_point(scene_model.body(body_index), result.base.point);
  const std::vector<double> times = core::output_times(options.end_time, options.output_step);

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
      const core::Model coupled = factory(core::FlexibleFormulation::kCoupled, scalings[uk]);
      const core::Model lte = factory(core::FlexibleFormulation::kLte, scalings[uk]);
      const double loose = options.estimate_factor * options.rtol;
      const Response c = integrate(coupled, body_index, point, times, options.solver, options.rtol);
      const Response l = integrate(lte, body_index, point, times, options.solver, options.rtol);
      const Response c_loose = integrate(coupled, body_index, point, times, options.solver, loose);
      const Response l_loose = integrate(lte, body_index, point, times, options.solver, loose);
      out.max_deflection = max_norm(c.deflection);
      if (!(out.max_deflection > 0.0)) {
        throw std::runtime_error("the coupled model's tracked point does not deflect");
      }
      out.tip_error = max_difference(l, c, out.max_deflection);
      out.attitude_error = max_angle(l, c);
      out.coupled_estimate = max_difference(c_loose, c, out.max_deflection);
      out.lte_estimate = max_difference(l_loose, l, out.max_deflection);
      out.resolved = out.tip_error >= 100.0 * std::max(out.coupled_estimate, out.lte_estimate);
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
  for (const LteMapPoint& p : result.points) {
    if (p.status != "ok") {
      ++failed;
    } else if (!p.resolved) {
      ++unresolved;
    }
  }
  if (unresolved > 0) {
    result.notes.push_back(std::to_string(unresolved) +
                           " grid point(s) marked '*' have an LTE error below 100x the "
                           "estimated error of a reference: the value is an upper bound, not a "
                           "measurement (tighten --rtol)");
  }
  if (failed > 0) {
    result.notes.push_back(std::to_string(failed) +
                           " grid point(s) failed (status in lte_map.csv); shown as '-'");
  }
  return result;
}

std::vector<double> lte_map_crossings(const LteMapResult& result, double level) {
  const std::size_t nx = result.options.spin_ratios.size();
  const std::size_t ny = result.options.inertia_ratios.size();
  std::vector<double> crossings(ny, kNaN);
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const LteMapPoint& a = result.points[j * nx + i];
      const LteMapPoint& b = result.points[j * nx + i + 1];
      if (!(a.tip_error > 0.0) || !(b.tip_error > 0.0)) continue;
      if ((a.tip_error - level) * (b.tip_error - level) > 0.0 || a.tip_error == b.tip_error) {
        continue;
      }
      const double f = std::log(level / a.tip_error) / std::log(b.tip_error / a.tip_error);
      crossings[j] = a.spin_ratio * std::pow(b.spin_ratio / a.spin_ratio, f);
      break;
    }
  }
  return crossings;
}

std::string lte_map_csv(const LteMapResult& result) {
  std::ostringstream s;
  s.precision(17);
  s << "spin_ratio,inertia_ratio,spin,omega1,hub_scale,load_scale,tip_error,"
       "attitude_error,max_deflection,coupled_estimate,lte_estimate,resolved,status\n";
  for (const LteMapPoint& p : result.points) {
    const std::string status = csv_text(p.status);
    s << p.spin_ratio << ',' << p.inertia_ratio << ',' << p.spin << ',' << p.omega1 << ','
      << p.hub_scale << ',' << p.load_scale << ',' << p.tip_error << ',' << p.attitude_error << ','
      << p.max_deflection << ',' << p.coupled_estimate << ',' << p.lte_estimate << ','
      << (p.resolved ? 1 : 0) << ',' << status << '\n';
  }
  return s.str();
}

std::string format_lte_map_table(const LteMapResult& result) {
  const LteMapBase& b = result.base;
  const std::size_t nx = result.options.spin_ratios.size();
  const std::size_t ny = result.options.inertia_ratios.size();
  std::ostringstream s;
  s << std::setprecision(4);
  s << "body '" << b.body << "', point '" << b.point << "': omega1 = " << b.omega1
    << " rad/s, scene Omega0/omega1 = " << b.spin_ratio
    << ", scene I_flex/I_rigid = " << b.inertia_ratio << "\n";
  s << "LTE tip-deflection error relative to the coupled model, % (rows: I_flex/I_rigid, "
       "columns: Omega0/omega1; * = below 100x the reference error estimate)\n";
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
      s << std::setw(9) << (percent(p.tip_error) + (p.status == "ok" && !p.resolved ? "*" : ""));
    }
    s << "\n";
  }
  for (const double level : {0.01, 0.05, 0.20}) {
    const std::vector<double> c = lte_map_crossings(result, level);
    s << percent(level) << " % line at Omega0/omega1 =";
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
  for (const std::string& note : result.notes) s << "note: " << note << "\n";
  return s.str();
}

}  // namespace flexref::studies
