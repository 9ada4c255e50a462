#include "contact/bushing.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "contact/bushing_tpl.hpp"
#include "contact/compliance.hpp"
#include "core/body.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::contact {
namespace {

using EndMotion = bushing::EndMotion<double>;
using bushing::separation;
using Separation = bushing::Separation<double>;

EndMotion end_motion(const BushingEnd& end, std::span<const core::BodyKinematics> bodies) {
  EndMotion m;
  if (end.body == kGround) {
    m.p_WP = end.point;
    m.axis_W = end.axis;
    return m;
  }
  const core::BodyKinematics& k = bodies[static_cast<std::size_t>(end.body)];
  m.ground = false;
  m.p_WP = k.p_WP(end.point);
  m.p_WBr = k.state->p_WBr;
  m.v_WBr = k.state->v_WBr;
  m.w_WB_W = k.R_WB * k.state->w_WB_B;
  m.axis_W = k.R_WB * end.axis;
  return m;
}

/// f = k d + c u on A at M, −f on B at M.
void add_spherical(const BushingEnd& a_end, const BushingEnd& b_end, const EndMotion& a,
                   const EndMotion& b, const BushingParameters& p,
                   std::span<core::Wrench> wrenches) {
  const Separation s = separation(a, b);
  const Eigen::Vector3d f_W = bushing::spherical_force(s, p);
  wrenches[static_cast<std::size_t>(a_end.body)].add_force_at(f_W, s.p_WM - a.p_WBr);
  if (!b.ground) {
    wrenches[static_cast<std::size_t>(b_end.body)].add_force_at(-f_W, s.p_WM - b.p_WBr);
  }
}

void validate(const BushingEnd& a, const BushingEnd& b, const BushingParameters& p, bool revolute) {
  if (a.body < 0) throw std::invalid_argument("bushing: the first end must be a body (index ≥ 0)");
  if (b.body < kGround)
    throw std::invalid_argument("bushing: invalid body index of the second end");
  if (a.body == b.body) throw std::invalid_argument("bushing: both ends on the same body");
  if (!a.point.allFinite() || !b.point.allFinite()) {
    throw std::invalid_argument("bushing: attachment point not finite");
  }
  const double values[] = {p.stiffness, p.damping, p.angular_stiffness, p.angular_damping};
  for (double v : values) {
    if (!std::isfinite(v) || v < 0.0) {
      throw std::invalid_argument("bushing: stiffness and damping must be finite and ≥ 0");
    }
  }
  if (revolute) {
    for (const BushingEnd* e : {&a, &b}) {
      const double n = e->axis.norm();
      if (!std::isfinite(n) || n == 0.0) {
        throw std::invalid_argument("bushing: hinge axis must be finite and non-zero");
      }
    }
  }
}

std::string vector_text(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return out.str();
}

std::string ends_text(const BushingEnd& a, const BushingEnd& b) {
  std::ostringstream out;
  out << "body " << a.body << " point " << vector_text(a.point) << " to ";
  if (b.body == kGround) {
    out << "ground point " << vector_text(b.point);
  } else {
    out << "body " << b.body << " point " << vector_text(b.point);
  }
  return out.str();
}

}  // namespace

double bushing_frequency(double stiffness, double effective_inertia) {
  return std::sqrt(stiffness / effective_inertia);
}

double bushing_stable_step(double stiffness, double damping, double effective_inertia) {
  if (stiffness <= 0.0) return std::numeric_limits<double>::infinity();
  const double omega = bushing_frequency(stiffness, effective_inertia);
  const double zeta = damping / (2.0 * std::sqrt(stiffness * effective_inertia));
  // √(1 + ζ²) − ζ = 1/(√(1 + ζ²) + ζ), without cancellation for large ζ.
  return 2.0 / omega / (std::sqrt(1.0 + zeta * zeta) + zeta);
}

// ---------------------------------------------------------------------------------------------
// SphericalBushing

SphericalBushing::SphericalBushing(const BushingEnd& a, const BushingEnd& b,
                                   const BushingParameters& parameters)
    : a_(a), b_(b), parameters_(parameters) {
  validate(a_, b_, parameters_, false);
  parameters_.angular_stiffness = 0.0;
  parameters_.angular_damping = 0.0;
}

void SphericalBushing::add_wrenches(const core::LoadContext& /*context*/,
                                    std::span<const core::BodyKinematics> bodies,
                                    std::span<core::Wrench> wrenches) const {
  add_spherical(a_, b_, end_motion(a_, bodies), end_motion(b_, bodies), parameters_, wrenches);
}

double SphericalBushing::potential_energy(const core::LoadContext& /*context*/,
                                          std::span<const core::BodyKinematics> bodies) const {
  return bushing::potential(end_motion(a_, bodies), end_motion(b_, bodies), parameters_, false);
}

double SphericalBushing::dissipated_power(const core::LoadContext& /*context*/,
                                          std::span<const core::BodyKinematics> bodies) const {
  return bushing::dissipated_power(end_motion(a_, bodies), end_motion(b_, bodies), parameters_,
                                   false);
}

int SphericalBushing::max_body_index() const { return std::max(a_.body, b_.body); }

std::string SphericalBushing::describe() const {
  std::ostringstream out;
  out << "spherical bushing: " << ends_text(a_, b_) << ", k = " << parameters_.stiffness
      << " N/m, c = " << parameters_.damping << " N·s/m";
  return out.str();
}

// ---------------------------------------------------------------------------------------------
// RevoluteBushing

RevoluteBushing::RevoluteBushing(const BushingEnd& a, const BushingEnd& b,
                                 const BushingParameters& parameters)
    : a_(a), b_(b), parameters_(parameters) {
  validate(a_, b_, parameters_, true);
  a_.axis.normalize();
  b_.axis.normalize();
}

void RevoluteBushing::add_wrenches(const core::LoadContext& /*context*/,
                                   std::span<const core::BodyKinematics> bodies,
                                   std::span<core::Wrench> wrenches) const {
  const EndMotion a = end_motion(a_, bodies);
  const EndMotion b = end_motion(b_, bodies);
  add_spherical(a_, b_, a, b, parameters_, wrenches);
  // τ_A = k_θ a_A × a_B + c_θ P (ω_B − ω_A), τ_B = −τ_A.
  const Eigen::Vector3d tau_W = bushing::revolute_torque(a, b, parameters_);
  wrenches[static_cast<std::size_t>(a_.body)].tau_Br_W += tau_W;
  wrenches[static_cast<std::size_t>(a_.body)].torque_magnitude += tau_W.norm();
  if (!b.ground) {
    wrenches[static_cast<std::size_t>(b_.body)].tau_Br_W -= tau_W;
    wrenches[static_cast<std::size_t>(b_.body)].torque_magnitude += tau_W.norm();
  }
}

double RevoluteBushing::potential_energy(const core::LoadContext& /*context*/,
                                         std::span<const core::BodyKinematics> bodies) const {
  return bushing::potential(end_motion(a_, bodies), end_motion(b_, bodies), parameters_, true);
}

double RevoluteBushing::dissipated_power(const core::LoadContext& /*context*/,
                                         std::span<const core::BodyKinematics> bodies) const {
  return bushing::dissipated_power(end_motion(a_, bodies), end_motion(b_, bodies), parameters_,
                                   true);
}

int RevoluteBushing::max_body_index() const { return std::max(a_.body, b_.body); }

std::string RevoluteBushing::describe() const {
  std::ostringstream out;
  out << "revolute bushing: " << ends_text(a_, b_) << ", hinge axis " << vector_text(a_.axis)
      << (b_.body == kGround ? " / world " : " / ") << vector_text(b_.axis)
      << ", k = " << parameters_.stiffness << " N/m, c = " << parameters_.damping
      << " N·s/m, k_theta = " << parameters_.angular_stiffness
      << " N·m/rad, c_theta = " << parameters_.angular_damping << " N·m·s/rad";
  return out.str();
}

namespace {

/// The two ends' compliances added (the ground adds none).
Compliance joint_compliance(std::span<const core::Body> bodies, const BushingEnd& a,
                            const BushingEnd& b) {
  Compliance c = body_compliance(bodies[static_cast<std::size_t>(a.body)], a.point);
  if (b.body != kGround) {
    const Compliance cb = body_compliance(bodies[static_cast<std::size_t>(b.body)], b.point);
    c.translational += cb.translational;
    c.angular += cb.angular;
  }
  return c;
}

core::PenaltyMode joint_mode(std::string label, double stiffness, double damping, double inertia) {
  core::PenaltyMode mode;
  mode.label = std::move(label);
  mode.kind = "joint";
  mode.stiffness = stiffness;
  mode.inertia = inertia;
  mode.frequency = bushing_frequency(stiffness, inertia);
  mode.step_limit = bushing_stable_step(stiffness, damping, inertia);
  return mode;
}

}  // namespace

void SphericalBushing::append_penalty_modes(std::span<const core::Body> bodies,
                                            std::vector<core::PenaltyMode>& modes) const {
  const Compliance c = joint_compliance(bodies, a_, b_);
  modes.push_back(joint_mode("", parameters_.stiffness, parameters_.damping,
                             smallest_effective(c.translational)));
}

void RevoluteBushing::append_penalty_modes(std::span<const core::Body> bodies,
                                           std::vector<core::PenaltyMode>& modes) const {
  const Compliance c = joint_compliance(bodies, a_, b_);
  modes.push_back(joint_mode(" translational", parameters_.stiffness, parameters_.damping,
                             smallest_effective(c.translational)));
  // The angular spring acts on rotations about directions perpendicular to the hinge (axis of
  // end a at the initial attitude).
  const core::Body& body_a = bodies[static_cast<std::size_t>(a_.body)];
  const Eigen::Vector3d axis_W =
      rotation::rotation_matrix(body_a.description().initial.theta_WB) * a_.axis;
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - axis_W * axis_W.transpose();
  modes.push_back(joint_mode(" angular", parameters_.angular_stiffness, parameters_.angular_damping,
                             smallest_effective(P * c.angular * P)));
}

}  // namespace flexref::contact
