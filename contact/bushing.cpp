#include "contact/bushing.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "contact/bushing_impl.hpp"
#include "contact/compliance.hpp"
#include "core/body.hpp"
#include "core/element_text.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::contact {
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

namespace detail {

void validate_bushing(const BushingEnd& a, const BushingEnd& b, const BushingParameters& p,
                      bool revolute) {
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

std::string bushing_ends_text(const BushingEnd& a, const BushingEnd& b,
                              std::span<const core::Body> bodies) {
  return core::body_text(a.body, bodies) + " point " + core::vector_text(a.point) + " to " +
         core::body_text(b.body, bodies) + " point " + core::vector_text(b.point);
}

void append_bushing_modes(std::span<const core::Body> bodies, const BushingEnd& a,
                          const BushingEnd& b, const BushingParameters& p, bool revolute,
                          std::vector<core::PenaltyMode>& modes) {
  const Compliance c = joint_compliance(bodies, a, b);
  modes.push_back(joint_mode(revolute ? " translational" : "", p.stiffness, p.damping,
                             smallest_effective(c.translational)));
  if (!revolute) return;
  // The angular spring acts on rotations about directions perpendicular to the hinge (axis of
  // end a at the initial attitude).
  const core::Body& body_a = bodies[static_cast<std::size_t>(a.body)];
  const Eigen::Vector3d axis_W =
      rotation::rotation_matrix(body_a.description().initial.theta_WB) * a.axis;
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - axis_W * axis_W.transpose();
  modes.push_back(joint_mode(" angular", p.angular_stiffness, p.angular_damping,
                             smallest_effective(P * c.angular * P)));
}

}  // namespace detail

template class BushingTpl<double, false>;
template class BushingTpl<double, true>;

}  // namespace flexref::contact
