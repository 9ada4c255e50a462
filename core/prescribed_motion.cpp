#include "core/prescribed_motion.hpp"

#include <cmath>
#include <sstream>

namespace flexref::core {

double AngleLaw::angle(double t) const { return angle_in<double>(t); }

double AngleLaw::angular_rate(double t) const { return angular_rate_in<double>(t); }

double AngleLaw::angular_acceleration(double t) const { return angular_acceleration_in<double>(t); }

std::string AngleLaw::describe() const {
  std::ostringstream out;
  if (kind == Kind::kConstantRate) {
    out << "constant rate " << rate << " rad/s";
  } else {
    out << "spin-up to " << rate << " rad/s over " << spin_up_time << " s";
  }
  return out.str();
}

PrescribedAttitude prescribed_attitude(const PrescribedRotation& rotation,
                                       const rotation::EulerParameters& theta_WB0, double t) {
  const double phi = rotation.law.angle(t);
  // θ(t) = q(φ a_W) ⊗ θ0: a rotation about a world axis composes on the left.
  rotation::EulerParameters q_axis;
  q_axis << std::cos(0.5 * phi), std::sin(0.5 * phi) * rotation.axis_W;
  PrescribedAttitude out;
  out.theta_WB = rotation::quaternion_multiply(q_axis, theta_WB0);
  const Eigen::Vector3d axis_B =
      rotation::rotation_matrix(out.theta_WB).transpose() * rotation.axis_W;
  out.w_WB_B = rotation.law.angular_rate(t) * axis_B;
  out.alpha_WB_B = rotation.law.angular_acceleration(t) * axis_B;
  return out;
}

}  // namespace flexref::core
