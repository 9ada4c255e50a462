#pragma once
/// \file exact_rotation_tpl.hpp
/// Euler-parameter algebra in any scalar type S, for the exact solutions written generically
/// (exact_torque_free_impl.hpp, exact_heavy_top_impl.hpp). The formulas are those of
/// rotation/euler_parameters.cpp (docs/design/model.md, Shabana §2.7), which stays the double
/// implementation the rest of flexref uses; with S = double these give the same numbers.
/// A(θ) in S is rotation::rotation_matrix<S> (rotation/euler_parameters.hpp).
/// Internal to the exact solutions: include only from their implementation headers.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace flexref::reference::detail {

template <typename S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <typename S>
using Quaternion = Eigen::Matrix<S, 4, 1>;  ///< Euler parameters (e0, e1, e2, e3)
template <typename S>
using Matrix3 = Eigen::Matrix<S, 3, 3>;

/// Hamilton product p ⊗ q (scalar first).
template <typename S>
Quaternion<S> quaternion_multiply(const Quaternion<S>& p, const Quaternion<S>& q) {
  const S p0 = p(0);
  const S q0 = q(0);
  const Vector3<S> pv = p.template tail<3>();
  const Vector3<S> qv = q.template tail<3>();
  Quaternion<S> r;
  r(0) = p0 * q0 - pv.dot(qv);
  r.template tail<3>() = p0 * qv + q0 * pv + pv.cross(qv);
  return r;
}

template <typename S>
Quaternion<S> quaternion_conjugate(const Quaternion<S>& q) {
  return Quaternion<S>(q(0), -q(1), -q(2), -q(3));
}

/// exp(φ̃) as Euler parameters (cos(|φ|/2), sin(|φ|/2) φ/|φ|).
template <typename S>
Quaternion<S> exp_quaternion(const Vector3<S>& phi) {
  using std::cos;
  using std::pow;
  using std::sin;
  const S angle = phi.norm();
  const S half = S(0.5) * angle;
  // sin(|φ|/2)/|φ| = ½ sinc(|φ|/2); Taylor to x⁴ below the x where the first neglected term
  // x⁶/5040 reaches ε: (5040 ε)^(1/6) = 1.0e-2 in double (rotation::exp_quaternion's 1e-2),
  // 1.3e-3 in extended, 3.8e-6 in quad.
  static const S threshold = pow(S(5040) * std::numeric_limits<S>::epsilon(), S(1) / S(6));
  S s;
  if (half < threshold) {
    const S h2 = half * half;
    s = S(0.5) * (S(1) - h2 / S(6) + h2 * h2 / S(120));
  } else {
    s = sin(half) / angle;
  }
  Quaternion<S> q;
  q(0) = cos(half);
  q.template tail<3>() = s * phi;
  return q;
}

/// Euler parameters of a rotation matrix (Shepperd, J. Guidance 1(3), 1978), e0 ≥ 0.
template <typename S>
Quaternion<S> euler_parameters_from_matrix(const Matrix3<S>& a) {
  using std::sqrt;
  const S trace = a.trace();
  Quaternion<S> q;
  const S quarter(0.25);
  if (trace > a(0, 0) && trace > a(1, 1) && trace > a(2, 2)) {
    const S s = S(2) * sqrt(S(1) + trace);  // 4 e0
    q << quarter * s, (a(2, 1) - a(1, 2)) / s, (a(0, 2) - a(2, 0)) / s, (a(1, 0) - a(0, 1)) / s;
  } else if (a(0, 0) > a(1, 1) && a(0, 0) > a(2, 2)) {
    const S s = S(2) * sqrt(S(1) + a(0, 0) - a(1, 1) - a(2, 2));  // 4 e1
    q << (a(2, 1) - a(1, 2)) / s, quarter * s, (a(0, 1) + a(1, 0)) / s, (a(0, 2) + a(2, 0)) / s;
  } else if (a(1, 1) > a(2, 2)) {
    const S s = S(2) * sqrt(S(1) + a(1, 1) - a(0, 0) - a(2, 2));  // 4 e2
    q << (a(0, 2) - a(2, 0)) / s, (a(0, 1) + a(1, 0)) / s, quarter * s, (a(1, 2) + a(2, 1)) / s;
  } else {
    const S s = S(2) * sqrt(S(1) + a(2, 2) - a(0, 0) - a(1, 1));  // 4 e3
    q << (a(1, 0) - a(0, 1)) / s, (a(0, 2) + a(2, 0)) / s, (a(1, 2) + a(2, 1)) / s, quarter * s;
  }
  if (q(0) < S(0)) q = -q;  // θ and −θ give the same A; the convention is e0 ≥ 0
  return q / q.norm();
}

}  // namespace flexref::reference::detail
