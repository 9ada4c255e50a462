#pragma once

/// \file prescribed_motion.hpp
/// Rigid motion `prescribed` (docs/design/model.md, "Rigid motion modes"): the body frame rotates
/// about a fixed world axis through its fixed origin Bo by a given angle law φ(t),
///
///   R_WB(t) = exp(φ(t) â_W) R_WB(0),   ω̄ = φ̇ R_WBᵀ a_W,   α̅ = φ̈ R_WBᵀ a_W
///
/// (a_W is fixed in the world, so d(Rᵀa_W)/dt = −ω̄ × Rᵀa_W = 0 because ω̄ ∥ Rᵀa_W). Only
/// the modal coordinates are integrated; the torque that drives the law is an output.

#include <Eigen/Core>
#include <boost/math/constants/constants.hpp>
#include <cmath>
#include <string>
#include <string_view>

#include "rotation/euler_parameters.hpp"

namespace flexref::core {

/// The angle law φ(t) about the axis, with its first two derivatives.
struct AngleLaw {
  enum class Kind {
    kConstantRate,  ///< φ = Ω t
    /// Kane–Ryan–Banerjee (1987) spin-up: φ = (Ω_s/T_s)[t²/2 + (T_s/2π)²(cos(2πt/T_s) − 1)]
    /// for t ≤ T_s, Ω_s (t − T_s/2) after; φ̇ rises smoothly from 0 to Ω_s (φ̈ is continuous).
    kSpinUp,
  };
  Kind kind = Kind::kConstantRate;
  double rate = 0.0;  ///< Ω (constant rate) or Ω_s (spin-up), rad/s (a prismatic drive: m/s)
  double spin_up_time = 1.0;  ///< T_s, s (spin-up only)

  /// φ, φ̇, φ̈ at t in any floating-point type S (double, long double, float128: the precision/
  /// references evaluate the law in their precision).
  template <typename S = double>
  S angle(S t) const;
  template <typename S = double>
  S angular_rate(S t) const;
  template <typename S = double>
  S angular_acceleration(S t) const;
  /// "constant rate 2 rad/s" / "spin-up to 2 rad/s over 15 s", the rate in `rate_unit`: rad/s
  /// for an angle, m/s for a prismatic drive's displacement (constraint::JointDrive).
  std::string describe(std::string_view rate_unit = "rad/s") const;
};

template <typename S>
S AngleLaw::angle(S t) const {
  using std::cos;
  const S two_pi = boost::math::constants::two_pi<S>();
  const S Omega(rate);
  if (kind == Kind::kConstantRate) return Omega * t;
  const S T(spin_up_time);
  if (t >= T) return Omega * (t - S(0.5) * T);
  const S c = T / two_pi;
  return (Omega / T) * (S(0.5) * t * t + c * c * (cos(two_pi * t / T) - S(1)));
}

template <typename S>
S AngleLaw::angular_rate(S t) const {
  using std::sin;
  const S two_pi = boost::math::constants::two_pi<S>();
  const S Omega(rate);
  if (kind == Kind::kConstantRate) return Omega;
  const S T(spin_up_time);
  if (t >= T) return Omega;
  // φ̇ = (Ω_s/T_s)[t − (T_s/2π) sin(2πt/T_s)]
  return (Omega / T) * (t - (T / two_pi) * sin(two_pi * t / T));
}

template <typename S>
S AngleLaw::angular_acceleration(S t) const {
  using std::cos;
  const S two_pi = boost::math::constants::two_pi<S>();
  if (kind == Kind::kConstantRate) return S(0);
  const S T(spin_up_time);
  if (t >= T) return S(0);
  // φ̈ = (Ω_s/T_s)[1 − cos(2πt/T_s)]
  return (S(rate) / T) * (S(1) - cos(two_pi * t / T));
}

/// A rotation about a fixed world axis through the fixed frame origin.
struct PrescribedRotation {
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitZ();  ///< unit
  AngleLaw law;
};

/// Attitude, body-frame angular velocity and acceleration at t, from the attitude at t = 0.
template <typename S>
struct PrescribedAttitudeTpl {
  Eigen::Matrix<S, 4, 1> theta_WB;
  Eigen::Matrix<S, 3, 1> w_WB_B;
  Eigen::Matrix<S, 3, 1> alpha_WB_B;
};
using PrescribedAttitude = PrescribedAttitudeTpl<double>;

/// θ(t) = q(φ a_W) ⊗ θ0 (a rotation about a world axis composes on the left), ω̄ = φ̇ Aᵀ a_W,
/// α̅ = φ̈ Aᵀ a_W, in any scalar type S with the axis and θ0 given in S.
template <typename S>
PrescribedAttitudeTpl<S> prescribed_attitude(const AngleLaw& law,
                                             const Eigen::Matrix<S, 3, 1>& axis_W,
                                             const Eigen::Matrix<S, 4, 1>& theta_WB0, S t) {
  using std::cos;
  using std::sin;
  const S phi = law.template angle<S>(t);
  Eigen::Matrix<S, 4, 1> q_axis;
  q_axis << cos(S(0.5) * phi), sin(S(0.5) * phi) * axis_W;
  PrescribedAttitudeTpl<S> out;
  out.theta_WB = rotation::quaternion_multiply<S>(q_axis, theta_WB0);
  const Eigen::Matrix<S, 3, 1> axis_B =
      rotation::rotation_matrix<S>(out.theta_WB).transpose() * axis_W;
  out.w_WB_B = law.template angular_rate<S>(t) * axis_B;
  out.alpha_WB_B = law.template angular_acceleration<S>(t) * axis_B;
  return out;
}

/// The same in double, from a body's description.
inline PrescribedAttitude prescribed_attitude(const PrescribedRotation& rotation,
                                              const rotation::EulerParameters& theta_WB0,
                                              double t) {
  return prescribed_attitude<double>(rotation.law, rotation.axis_W, theta_WB0, t);
}

}  // namespace flexref::core
