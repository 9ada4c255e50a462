#include "reference/exact_pendulum.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace flexref::reference {

PendulumExact::PendulumExact(double mass, const Eigen::Vector3d& c_B,
                             const Eigen::Matrix3d& j_pivot_B, const Eigen::Vector3d& g_W,
                             const rotation::EulerParameters& theta0)
    : theta0_(detail::unit_euler_parameters(theta0, "PendulumExact")) {
  if (!std::isfinite(mass) || !(mass > 0.0)) {
    throw std::invalid_argument("PendulumExact: mass must be finite and > 0");
  }
  if (!c_B.allFinite() || !g_W.allFinite() || !j_pivot_B.allFinite()) {
    throw std::invalid_argument("PendulumExact: non-finite input");
  }
  const double j_norm = j_pivot_B.norm();
  if ((j_pivot_B - j_pivot_B.transpose()).norm() > 1e-12 * j_norm) {
    throw std::invalid_argument("PendulumExact: inertia about the pivot must be symmetric");
  }
  const Eigen::Matrix3d attitude0 = rotation::rotation_matrix(theta0_);
  const Eigen::Vector3d c_W = attitude0 * c_B;
  const Eigen::Vector3d cross = c_W.cross(g_W);
  if (cross.isZero(0.0)) return;  // c = 0, g = 0 or c ∥ g: equilibrium, stays at rest
  at_rest_ = false;
  axis_W_ = cross.normalized();
  axis_B_ = attitude0.transpose() * axis_W_;
  const double j_n = axis_B_.dot(j_pivot_B * axis_B_);
  if (!(j_n > 0.0)) {
    throw std::invalid_argument("PendulumExact: inertia about the rotation axis must be > 0");
  }
  // Planar motion needs J n ∥ n; the residual J n − J_n n couples into the other axes.
  if ((j_pivot_B * axis_B_ - j_n * axis_B_).norm() > 1e-12 * j_norm) {
    throw std::invalid_argument(
        "PendulumExact: the rotation axis (A c) x g is not a principal axis of the inertia "
        "about the pivot; the motion would not be planar");
  }
  const double gravity = g_W.norm();
  const double length = c_B.norm();
  omega0_ = std::sqrt(mass * gravity * length / j_n);
  // Half-angles of θ₀ (angle between c and down) from chords of the unit vectors.
  const Eigen::Vector3d c_hat = c_W / length;
  const Eigen::Vector3d down = g_W / gravity;
  const double half_sin = 0.5 * (c_hat - down).norm();
  const double half_cos = 0.5 * (c_hat + down).norm();
  const double scale = std::hypot(half_sin, half_cos);
  k_ = half_sin / scale;
  k_prime_ = half_cos / scale;
  amplitude_ = 2.0 * std::atan2(k_, k_prime_);
  quarter_period_ = elliptic::complete_k(k_prime_);
}

double PendulumExact::period() const {
  if (at_rest_) return std::numeric_limits<double>::infinity();
  return 4.0 * quarter_period_ / omega0_;
}

RigidAttitude PendulumExact::at(double t) const {
  if (at_rest_) return {theta0_, Eigen::Vector3d::Zero()};
  const elliptic::JacobiValues f = elliptic::jacobi(quarter_period_ - omega0_ * t, k_, k_prime_);
  // θ/2 has sine k sn and cosine dn; the rotation from the release is δ = θ₀ − θ about n:
  // cos(δ/2) = k' dn + k² sn, sin(δ/2) = k (dn − k' sn).
  const double cos_half = k_prime_ * f.dn + k_ * k_ * f.sn;
  const double sin_half = k_ * (f.dn - k_prime_ * f.sn);
  rotation::EulerParameters rotation;
  rotation(0) = cos_half;
  rotation.tail<3>() = sin_half * axis_W_;
  RigidAttitude result;
  result.theta = rotation::quaternion_multiply(rotation, theta0_);
  result.w_B = (2.0 * k_ * omega0_ * f.cn) * axis_B_;  // δ̇ = −θ̇ = 2kω₀ cn
  return result;
}

}  // namespace flexref::reference
