#include "contact/contact.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/body.hpp"

namespace flexref::contact {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

/// World position of a sphere centre (from Bo, body frame; deformed when at a node).
Eigen::Vector3d centre_W(const core::BodyKinematics& k, const Eigen::Vector3d& p_BoC_B,
                         const core::NodeAttachment& node) {
  return core::attached_position_W(k, p_BoC_B, node);
}

/// Velocity of the sphere's material point at the world point P:
/// v_Br + ω × (P − p_WBr) (+ A Φ_k q̇_f at a node).
Eigen::Vector3d material_velocity_W(const core::BodyKinematics& k, const Eigen::Vector3d& p_WP,
                                    const core::NodeAttachment& node) {
  return core::attached_velocity_W(k, p_WP, node);
}

}  // namespace

ContactPair ContactPair::sphere_plane(int body, const Eigen::Vector3d& p_BoC_B, double radius,
                                      const Eigen::Vector3d& p_WQ, const Eigen::Vector3d& n_W) {
  require(body >= 0, "contact sphere body index must be >= 0");
  require(radius >= 0.0 && std::isfinite(radius), "contact sphere radius must be >= 0");
  require(finite(p_BoC_B) && finite(p_WQ) && finite(n_W), "contact geometry must be finite");
  const double norm = n_W.norm();
  require(norm > 0.0 && std::isfinite(norm), "contact plane normal must be nonzero");
  ContactPair p;
  p.kind = Kind::kSpherePlane;
  p.body_b = body;
  p.p_BoCb_B = p_BoC_B;
  p.radius_b = radius;
  p.p_WQ = p_WQ;
  p.n_W = n_W / norm;
  return p;
}

ContactPair ContactPair::point_plane(int body, const Eigen::Vector3d& p_BoP_B,
                                     const Eigen::Vector3d& p_WQ, const Eigen::Vector3d& n_W) {
  return sphere_plane(body, p_BoP_B, 0.0, p_WQ, n_W);
}

ContactPair ContactPair::sphere_sphere(int body_a, const Eigen::Vector3d& p_BoCa_B, double radius_a,
                                       int body_b, const Eigen::Vector3d& p_BoCb_B,
                                       double radius_b) {
  require(body_a >= 0 && body_b >= 0, "contact sphere body indices must be >= 0");
  require(body_a != body_b, "sphere-sphere contact needs two different bodies");
  require(radius_a >= 0.0 && radius_b >= 0.0 && std::isfinite(radius_a) && std::isfinite(radius_b),
          "contact sphere radii must be >= 0");
  require(finite(p_BoCa_B) && finite(p_BoCb_B), "contact geometry must be finite");
  ContactPair p;
  p.kind = Kind::kSphereSphere;
  p.body_a = body_a;
  p.p_BoCa_B = p_BoCa_B;
  p.radius_a = radius_a;
  p.body_b = body_b;
  p.p_BoCb_B = p_BoCb_B;
  p.radius_b = radius_b;
  return p;
}

ContactPoint contact_point(const ContactPair& pair, std::span<const core::BodyKinematics> bodies) {
  const Eigen::Vector3d p_WCb =
      centre_W(bodies[static_cast<std::size_t>(pair.body_b)], pair.p_BoCb_B, pair.node_b);
  if (pair.kind == ContactPair::Kind::kSpherePlane) {
    return sphere_plane_point_tpl<double>(p_WCb, pair.radius_b, pair.p_WQ, pair.n_W);
  }
  const Eigen::Vector3d p_WCa =
      centre_W(bodies[static_cast<std::size_t>(pair.body_a)], pair.p_BoCa_B, pair.node_a);
  return sphere_sphere_point_tpl<double>(p_WCa, pair.radius_a, p_WCb, pair.radius_b);
}

ContactElement::ContactElement(std::vector<ContactPair> pairs, NormalLaw normal,
                               FrictionLaw friction, double effective_mass, std::string name)
    : pairs_(std::move(pairs)),
      normal_(std::move(normal)),
      friction_(friction),
      effective_mass_(effective_mass),
      name_(std::move(name)) {
  require(friction_.mu >= 0.0 && std::isfinite(friction_.mu), "friction coefficient must be >= 0");
  require(friction_.v_reg > 0.0 && std::isfinite(friction_.v_reg),
          "friction regularization speed must be > 0");
  require(effective_mass_ >= 0.0 && std::isfinite(effective_mass_),
          "contact effective mass must be >= 0");
}

ContactEvaluation ContactElement::evaluate(int pair_index,
                                           std::span<const core::BodyKinematics> bodies) const {
  const ContactPair& pair = pairs_[static_cast<std::size_t>(pair_index)];
  ContactEvaluation e;
  e.point = contact_point(pair, bodies);
  if (e.point.gap >= 0.0) return e;  // separated (or touching): no force
  const Eigen::Vector3d& n = e.point.n_W;
  e.v_rel_W =
      material_velocity_W(bodies[static_cast<std::size_t>(pair.body_b)], e.point.p_WP, pair.node_b);
  if (pair.body_a >= 0) {
    e.v_rel_W -= material_velocity_W(bodies[static_cast<std::size_t>(pair.body_a)], e.point.p_WP,
                                     pair.node_a);
  }
  static_cast<PenaltyLoadTpl<double>&>(e) =
      penalty_load_tpl<double>(normal_, friction_, e.point.gap, n, e.v_rel_W);
  return e;
}

void ContactElement::add_wrenches(const core::LoadContext& /*context*/,
                                  std::span<const core::BodyKinematics> bodies,
                                  std::span<core::Wrench> wrenches) const {
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    const ContactEvaluation e = evaluate(static_cast<int>(i), bodies);
    if (e.normal.total == 0.0) continue;
    const ContactPair& pair = pairs_[i];
    const Eigen::Vector3d f_W = e.force_on_b_W();
    const auto b = static_cast<std::size_t>(pair.body_b);
    core::add_attached_force(bodies[b], pair.node_b, f_W, e.point.p_WP, wrenches[b]);
    if (pair.body_a >= 0) {
      const auto a = static_cast<std::size_t>(pair.body_a);
      core::add_attached_force(bodies[a], pair.node_a, -f_W, e.point.p_WP, wrenches[a]);
    }
  }
}

double ContactElement::potential_energy(const core::LoadContext& /*context*/,
                                        std::span<const core::BodyKinematics> bodies) const {
  double v = 0.0;
  for (const ContactPair& pair : pairs_) v += normal_.potential(-contact_point(pair, bodies).gap);
  return v;
}

double ContactElement::dissipated_power(const core::LoadContext& /*context*/,
                                        std::span<const core::BodyKinematics> bodies) const {
  double p = 0.0;
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    p += evaluate(static_cast<int>(i), bodies).dissipated_power();
  }
  return p;
}

void ContactElement::wear_samples(const core::LoadContext& /*context*/,
                                  std::span<const core::BodyKinematics> bodies,
                                  std::span<core::WearSample> samples) const {
  core::WearSample& w = samples[0];
  w = core::WearSample{};
  double largest = 0.0;
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    const ContactEvaluation e = evaluate(static_cast<int>(i), bodies);
    if (e.normal.total == 0.0) continue;
    w.normal_force += e.normal.total;
    w.wear_power += std::abs(e.f_friction_W.dot(e.v_t_W));  // |F_t·v_t|
    if (e.normal.total > largest) {
      largest = e.normal.total;
      w.slip_speed = e.v_t_W.norm();
    }
  }
}

void ContactElement::switching_functions(const core::LoadContext& /*context*/,
                                         std::span<const core::BodyKinematics> bodies,
                                         std::span<double> g) const {
  for (std::size_t i = 0; i < pairs_.size(); ++i) g[i] = contact_point(pairs_[i], bodies).gap;
}

int ContactElement::max_body_index() const {
  int m = -1;
  for (const ContactPair& p : pairs_) m = std::max({m, p.body_a, p.body_b});
  return m;
}

double ContactElement::effective_stiffness(double effective_mass) const {
  if (normal_.kind() == NormalLaw::Kind::kLinear) return normal_.stiffness();
  return normal_.linearized_stiffness(
      normal_.impact_penetration(effective_mass, normal_.reference_speed()));
}

double ContactElement::frequency(double effective_mass) const {
  return std::sqrt(effective_stiffness(effective_mass) / effective_mass);
}

double ContactElement::explicit_step_limit(double effective_mass) const {
  return 2.0 / frequency(effective_mass);
}

void ContactElement::append_penalty_modes(std::span<const core::Body> bodies,
                                          std::vector<core::PenaltyMode>& modes) const {
  double m_eff = effective_mass_;
  if (!(m_eff > 0.0)) {
    // body_b is the sphere body pushed along +n; body_a is −1 for the ground plane.
    const ContactPair& p = pairs_.front();
    double m = bodies[static_cast<std::size_t>(p.body_b)].mass();
    if (p.body_a >= 0) {
      const double m_a = bodies[static_cast<std::size_t>(p.body_a)].mass();
      m = m * m_a / (m + m_a);
    }
    m_eff = m / static_cast<double>(pairs_.size());
  }
  core::PenaltyMode mode;
  mode.kind = "contact";
  mode.inertia = m_eff;
  mode.stiffness = effective_stiffness(m_eff);
  mode.frequency = frequency(m_eff);
  mode.step_limit = explicit_step_limit(m_eff);
  modes.push_back(mode);
}

std::string ContactElement::describe() const {
  std::ostringstream out;
  int planes = 0;
  int nodes = 0;
  for (const ContactPair& p : pairs_) nodes += p.node_a.deforms() + p.node_b.deforms();
  for (const ContactPair& p : pairs_) planes += p.kind == ContactPair::Kind::kSpherePlane;
  out << "contact: " << planes << " sphere-plane and "
      << pairs_.size() - static_cast<std::size_t>(planes) << " sphere-sphere pairs, "
      << normal_.describe() << ", friction mu = " << friction_.mu << ", v_reg = " << friction_.v_reg
      << " m/s";
  if (nodes > 0) out << ", " << nodes << " sphere(s) at deforming nodes";
  if (!name_.empty()) out << ", wear outputs '" << name_ << "'";
  if (effective_mass_ > 0.0) {
    out << "; m_eff = " << effective_mass_
        << " kg: k_eff = " << effective_stiffness(effective_mass_)
        << " N/m, omega = " << frequency(effective_mass_)
        << " rad/s, explicit step limit 2/omega = " << explicit_step_limit(effective_mass_) << " s";
    if (normal_.kind() == NormalLaw::Kind::kLinear) {
      out << " (zeta = "
          << normal_.damping() / (2.0 * std::sqrt(normal_.stiffness() * effective_mass_)) << ")";
    }
  }
  return out.str();
}

}  // namespace flexref::contact
