#pragma once
/// \file exact_pendulum_impl.hpp
/// The body of PendulumExactTpl (exact_pendulum.hpp), written once for any scalar type S.
/// Include only where the template is explicitly instantiated (exact_pendulum.cpp for double,
/// precision/exact_solution_instances.cpp for long double and float128).
#include <cmath>
#include <limits>
#include <stdexcept>

#include "reference/exact_pendulum.hpp"
#include "reference/exact_rotation_tpl.hpp"
#include "reference/exact_torque_free_impl.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::reference {

template <typename S>
PendulumExactTpl<S>::PendulumExactTpl(S mass, const Vector3& c_B, const Matrix3& j_pivot_B,
                                      const Vector3& g_W, const Quaternion& theta0)
    : theta0_(detail::unit_euler_parameters<S>(theta0, "PendulumExact")) {
  using std::atan2;
  using std::hypot;
  using std::isfinite;
  using std::sqrt;
  if (!static_cast<bool>(isfinite(mass)) || !(mass > S(0))) {
    throw std::invalid_argument("PendulumExact: mass must be finite and > 0");
  }
  if (!c_B.allFinite() || !g_W.allFinite() || !j_pivot_B.allFinite()) {
    throw std::invalid_argument("PendulumExact: non-finite input");
  }
  // 1e-12: the data's symmetry and principal-axis tolerances (scenes give decimal inertias),
  // not rounding thresholds of S.
  const S j_norm = j_pivot_B.norm();
  if ((j_pivot_B - j_pivot_B.transpose()).norm() > S(1e-12) * j_norm) {
    throw std::invalid_argument("PendulumExact: inertia about the pivot must be symmetric");
  }
  const Matrix3 attitude0 = rotation::rotation_matrix<S>(theta0_);
  const Vector3 c_W = attitude0 * c_B;
  const Vector3 cross = c_W.cross(g_W);
  if (cross(0) == S(0) && cross(1) == S(0) && cross(2) == S(0)) {
    return;  // c = 0, g = 0 or c ∥ g: equilibrium, stays at rest
  }
  at_rest_ = false;
  axis_W_ = cross.normalized();
  axis_B_ = attitude0.transpose() * axis_W_;
  const S j_n = axis_B_.dot(j_pivot_B * axis_B_);
  if (!(j_n > S(0))) {
    throw std::invalid_argument("PendulumExact: inertia about the rotation axis must be > 0");
  }
  // Planar motion needs J n ∥ n; the residual J n − J_n n couples into the other axes.
  if ((j_pivot_B * axis_B_ - j_n * axis_B_).norm() > S(1e-12) * j_norm) {
    throw std::invalid_argument(
        "PendulumExact: the rotation axis (A c) x g is not a principal axis of the inertia "
        "about the pivot; the motion would not be planar");
  }
  const S gravity = g_W.norm();
  const S length = c_B.norm();
  omega0_ = sqrt(mass * gravity * length / j_n);
  // Half-angles of θ₀ (angle between c and down) from chords of the unit vectors.
  const Vector3 c_hat = c_W / length;
  const Vector3 down = g_W / gravity;
  const S half_sin = S(0.5) * (c_hat - down).norm();
  const S half_cos = S(0.5) * (c_hat + down).norm();
  const S scale = hypot(half_sin, half_cos);
  k_ = half_sin / scale;
  k_prime_ = half_cos / scale;
  amplitude_ = S(2) * atan2(k_, k_prime_);
  quarter_period_ = elliptic::complete_k<S>(k_prime_);
}

template <typename S>
S PendulumExactTpl<S>::period() const {
  if (at_rest_) return std::numeric_limits<S>::infinity();
  return S(4) * quarter_period_ / omega0_;
}

template <typename S>
RigidAttitudeTpl<S> PendulumExactTpl<S>::at(S t) const {
  if (at_rest_) return {theta0_, Vector3::Zero()};
  const elliptic::JacobiValuesTpl<S> f =
      elliptic::jacobi<S>(quarter_period_ - omega0_ * t, k_, k_prime_);
  // θ/2 has sine k sn and cosine dn; the rotation from the release is δ = θ₀ − θ about n:
  // cos(δ/2) = k' dn + k² sn, sin(δ/2) = k (dn − k' sn).
  const S cos_half = k_prime_ * f.dn + k_ * k_ * f.sn;
  const S sin_half = k_ * (f.dn - k_prime_ * f.sn);
  Quaternion rotation;
  rotation(0) = cos_half;
  rotation.template tail<3>() = sin_half * axis_W_;
  RigidAttitudeTpl<S> result;
  result.theta = detail::quaternion_multiply<S>(rotation, theta0_);
  result.w_B = (S(2) * k_ * omega0_ * f.cn) * axis_B_;  // δ̇ = −θ̇ = 2kω₀ cn
  return result;
}

}  // namespace flexref::reference
