#include "core/prescribed_motion.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace flexref::core {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
}  // namespace

double AngleLaw::angle(double t) const {
  if (kind == Kind::kConstantRate) return rate * t;
  const double T = spin_up_time;
  if (t >= T) return rate * (t - 0.5 * T);
  const double c = T / kTwoPi;
  return (rate / T) * (0.5 * t * t + c * c * (std::cos(kTwoPi * t / T) - 1.0));
}

double AngleLaw::angular_rate(double t) const {
  if (kind == Kind::kConstantRate) return rate;
  const double T = spin_up_time;
  if (t >= T) return rate;
  // φ̇ = (Ω_s/T_s)[t − (T_s/2π) sin(2πt/T_s)]
  return (rate / T) * (t - (T / kTwoPi) * std::sin(kTwoPi * t / T));
}

double AngleLaw::angular_acceleration(double t) const {
  if (kind == Kind::kConstantRate) return 0.0;
  const double T = spin_up_time;
  if (t >= T) return 0.0;
  // φ̈ = (Ω_s/T_s)[1 − cos(2πt/T_s)]
  return (rate / T) * (1.0 - std::cos(kTwoPi * t / T));
}

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
