#include "contact/gap_support.hpp"

#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "contact/gap_support_tpl.hpp"
#include "core/body.hpp"

namespace flexref::contact {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

GapSupport::GapSupport(int body, const Eigen::Vector3d& p_BoN_B, core::NodeAttachment node,
                       GapSupportGeometry geometry, NormalLaw normal, FrictionLaw friction,
                       double effective_mass, std::string name)
    : body_(body),
      p_BoN_B_(p_BoN_B),
      node_(std::move(node)),
      geometry_(std::move(geometry)),
      normal_(std::move(normal)),
      friction_(friction),
      effective_mass_(effective_mass),
      name_(std::move(name)) {
  require(body_ >= 0, "gap support body index must be >= 0");
  require(p_BoN_B_.allFinite() && geometry_.p_WS.allFinite(),
          "gap support geometry must be finite");
  require(geometry_.clearance > 0.0 && std::isfinite(geometry_.clearance),
          "gap support clearance must be > 0");
  const double a = geometry_.a_W.norm();
  require(std::isfinite(a) && a > 0.0, "gap support axis must be nonzero");
  geometry_.a_W /= a;
  if (geometry_.kind == GapSupportGeometry::Kind::kPlanar) {
    // m projected on the plane normal to the axis, then normalized.
    const Eigen::Vector3d m = geometry_.m_W - geometry_.a_W.dot(geometry_.m_W) * geometry_.a_W;
    require(m.allFinite() && m.norm() > 1e-12 * geometry_.m_W.norm(),
            "gap support plane normal must not be parallel to the axis");
    geometry_.m_W = m.normalized();
  }
  require(friction_.mu >= 0.0 && std::isfinite(friction_.mu), "friction coefficient must be >= 0");
  require(friction_.v_reg > 0.0 && std::isfinite(friction_.v_reg),
          "friction regularization speed must be > 0");
  require(effective_mass_ >= 0.0 && std::isfinite(effective_mass_),
          "gap support effective mass must be >= 0");
  geometry_in_s_ = geometry_in<double>();
}

GapPoint GapSupport::gap_point(std::span<const core::BodyKinematics> bodies) const {
  GapPoint c;
  c.p_WN = core::attached_position_W(bodies[static_cast<std::size_t>(body_)], p_BoN_B_, node_);
  const GapPointTpl<double> g = gap_point_tpl<double>(geometry_in_s_, c.p_WN);
  c.gap = g.gap;
  c.n_W = g.n_W;
  return c;
}

GapSupport::Evaluation GapSupport::evaluate(std::span<const core::BodyKinematics> bodies) const {
  Evaluation e;
  e.point = gap_point(bodies);
  if (e.point.gap >= 0.0) return e;
  const Eigen::Vector3d v =
      core::attached_velocity_W(bodies[static_cast<std::size_t>(body_)], e.point.p_WN, node_);
  static_cast<PenaltyLoadTpl<double>&>(e) =
      penalty_load_tpl<double>(normal_, friction_, e.point.gap, e.point.n_W, v);
  return e;
}

void GapSupport::add_wrenches(const core::LoadContext& /*context*/,
                              std::span<const core::BodyKinematics> bodies,
                              std::span<core::Wrench> wrenches) const {
  const Evaluation e = evaluate(bodies);
  if (e.normal.total == 0.0) return;
  const auto b = static_cast<std::size_t>(body_);
  core::add_attached_force(bodies[b], node_, e.force_W(), e.point.p_WN, wrenches[b]);
}

double GapSupport::potential_energy(const core::LoadContext& /*context*/,
                                    std::span<const core::BodyKinematics> bodies) const {
  return normal_.potential(-gap_point(bodies).gap);
}

double GapSupport::dissipated_power(const core::LoadContext& /*context*/,
                                    std::span<const core::BodyKinematics> bodies) const {
  return evaluate(bodies).dissipated_power();
}

void GapSupport::switching_functions(const core::LoadContext& /*context*/,
                                     std::span<const core::BodyKinematics> bodies,
                                     std::span<double> g) const {
  g[0] = gap_point(bodies).gap;
}

void GapSupport::wear_samples(const core::LoadContext& /*context*/,
                              std::span<const core::BodyKinematics> bodies,
                              std::span<core::WearSample> samples) const {
  const Evaluation e = evaluate(bodies);
  core::WearSample& w = samples[0];
  w = core::WearSample{};
  if (e.normal.total == 0.0) return;
  w.normal_force = e.normal.total;
  w.slip_speed = e.v_t_W.norm();
  w.wear_power = std::abs(e.f_friction_W.dot(e.v_t_W));  // |F_t·v_t|
}

std::string GapSupport::describe() const {
  std::ostringstream out;
  const bool circular = geometry_.kind == GapSupportGeometry::Kind::kCircular;
  out << "gap support: " << (circular ? "circular" : "planar") << " clearance "
      << geometry_.clearance << " m around the axis through (" << geometry_.p_WS.transpose()
      << ") along (" << geometry_.a_W.transpose() << ")";
  if (!circular) out << ", planes normal to (" << geometry_.m_W.transpose() << ")";
  out << (node_.deforms() ? ", at node " + std::to_string(node_.node)
                          : std::string(", at a body point"))
      << ", " << normal_.describe() << ", friction mu = " << friction_.mu
      << ", v_reg = " << friction_.v_reg << " m/s";
  if (!name_.empty()) out << ", wear outputs '" << name_ << "'";
  return out.str();
}

void GapSupport::append_penalty_modes(std::span<const core::Body> bodies,
                                      std::vector<core::PenaltyMode>& modes) const {
  const double m_eff =
      effective_mass_ > 0.0 ? effective_mass_ : bodies[static_cast<std::size_t>(body_)].mass();
  core::PenaltyMode mode;
  mode.kind = "contact";
  mode.inertia = m_eff;
  mode.stiffness = normal_.kind() == NormalLaw::Kind::kLinear
                       ? normal_.stiffness()
                       : normal_.linearized_stiffness(
                             normal_.impact_penetration(m_eff, normal_.reference_speed()));
  mode.frequency = std::sqrt(mode.stiffness / m_eff);
  mode.step_limit = 2.0 / mode.frequency;
  modes.push_back(mode);
  if (!(friction_.mu > 0.0)) return;
  // Regularized friction below v_reg is a viscous damper c_t = μ F_n/v_reg (docs/contact.md); at
  // the normal force F_n of an impact at the law's reference speed (Hunt–Crossley) or at
  // k·(clearance) (linear) it bounds central differences by 2 m_eff/c_t (a first-order decay
  // with rate c_t/m_eff). On tube_support_impact: 9.5e-5 s; C2 runs at 1e-4 and diverges at 2e-4.
  const double delta = normal_.kind() == NormalLaw::Kind::kLinear
                           ? geometry_.clearance
                           : normal_.impact_penetration(m_eff, normal_.reference_speed());
  const double f_n = normal_.force(delta, 0.0).elastic;
  core::PenaltyMode f;
  f.label = " friction";
  f.kind = "contact";
  f.inertia = m_eff;
  f.stiffness = 0.0;
  const double c_t = friction_.mu * f_n / friction_.v_reg;
  f.frequency = c_t / m_eff;  // the decay rate, 1/s
  f.step_limit = 2.0 * m_eff / c_t;
  modes.push_back(f);
}

}  // namespace flexref::contact
