/// \file lte_map_grid.cpp
/// The lte-map's grid points (studies/lte_map_grid.hpp): base values, hub scaling, the model
/// factory.
#include "studies/lte_map_grid.hpp"

#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "scene/build_model.hpp"

namespace flexref::studies {
namespace {

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

}  // namespace

int lte_map_body(const core::Model& model, int requested) {
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

const core::TrackedPoint& lte_map_point(const core::Body& body, const std::string& name) {
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

LteMapBase lte_map_base(const core::Model& model, int body_index, const std::string& point) {
  const int index = lte_map_body(model, body_index);
  const core::Body& body = model.body(index);
  LteMapBase base;
  base.body = body.name();
  base.point = lte_map_point(body, point).name;
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

}  // namespace flexref::studies
