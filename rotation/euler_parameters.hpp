#pragma once
/// \file euler_parameters.hpp
/// Euler parameters θ = (e0, e1, e2, e3), scalar first, θᵀθ = 1, describing the rotation
/// body → global (docs/design/model.md, Shabana "Dynamics of multibody systems" §2.7):
///   A  = (2e0² − 1) I + 2 (e eᵀ + e0 ẽ)
///   Ḡ  = [−e  e0 I − ẽ],  G = [−e  e0 I + ẽ],  A = G Ḡᵀ
///   ω̄  = 2 Ḡ θ̇,  ω = 2 G θ̇,  θ̇ = ½ Ḡᵀ ω̄ = ½ θ ⊗ (0, ω̄)
/// The small maps on every evaluation's path (A, Ḡ, G, the product, the rate) are inline here:
/// they cross every library boundary, and inline they need no link-time optimization
/// (docs/performance.md, "Build").
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <type_traits>

namespace flexref::rotation {

using EulerParameters = Eigen::Vector4d;  ///< (e0, e1, e2, e3), scalar first
using Matrix34d = Eigen::Matrix<double, 3, 4>;

inline EulerParameters identity_euler_parameters() { return EulerParameters(1.0, 0.0, 0.0, 0.0); }
/// Hamilton product p ⊗ q (scalar first); rotation of q followed by p in the body→global sense.
inline EulerParameters quaternion_multiply(const EulerParameters& p, const EulerParameters& q) {
  const double p0 = p(0);
  const double q0 = q(0);
  const Eigen::Vector3d pv = p.tail<3>();
  const Eigen::Vector3d qv = q.tail<3>();
  EulerParameters r;
  r(0) = p0 * q0 - pv.dot(qv);
  r.tail<3>() = p0 * qv + q0 * pv + pv.cross(qv);
  return r;
}
/// The same product in any scalar type S (the same operations: double's calls agree bit for bit).
template <typename S>
Eigen::Matrix<S, 4, 1> quaternion_multiply(const Eigen::Matrix<S, 4, 1>& p,
                                           const Eigen::Matrix<S, 4, 1>& q) {
  const Eigen::Matrix<S, 3, 1> pv = p.template tail<3>();
  const Eigen::Matrix<S, 3, 1> qv = q.template tail<3>();
  Eigen::Matrix<S, 4, 1> r;
  r(0) = p(0) * q(0) - pv.dot(qv);
  r.template tail<3>() = p(0) * qv + q(0) * pv + pv.cross(qv);
  return r;
}
inline EulerParameters quaternion_conjugate(const EulerParameters& q) {
  return EulerParameters(q(0), -q(1), -q(2), -q(3));
}

/// A(θ), body → global (exact rotation for unit θ), in any scalar type S (double, long double,
/// float128: the exact solutions and the precision models use it in S).
template <typename S>
Eigen::Matrix<S, 3, 3> rotation_matrix(const Eigen::Matrix<S, 4, 1>& theta) {
  // A = (2e0² − 1) I + 2 (e eᵀ + e0 ẽ), written out entry by entry (this is on every
  // evaluation's path). S(2) and S(1) are the literals 2.0 and 1.0 in double.
  const S e0 = theta(0), e1 = theta(1), e2 = theta(2), e3 = theta(3);
  const S d = S(2) * e0 * e0 - S(1);
  Eigen::Matrix<S, 3, 3> a;
  a << d + S(2) * e1 * e1, S(2) * (e1 * e2 - e0 * e3), S(2) * (e1 * e3 + e0 * e2),  //
      S(2) * (e1 * e2 + e0 * e3), d + S(2) * e2 * e2, S(2) * (e2 * e3 - e0 * e1),   //
      S(2) * (e1 * e3 - e0 * e2), S(2) * (e2 * e3 + e0 * e1), d + S(2) * e3 * e3;
  return a;
}
/// A(θ) in double; also takes Eigen expressions (−θ, θ.normalized(), ...).
inline Eigen::Matrix3d rotation_matrix(const EulerParameters& theta) {
  return rotation_matrix<double>(theta);
}
/// A(θ/|θ|) for Euler parameters of any nonzero norm (model.md eq. (1)):
/// I + (2/|θ|²)(e eᵀ + e0 ẽ − |e|² I) entry by entry, a rotation whatever |θ| an integrated state
/// has (the precision models use it). For a unit θ it is A(θ) with other roundings, so it does
/// not replace rotation_matrix where double output must stay bit for bit.
template <typename S>
Eigen::Matrix<S, 3, 3> rotation_matrix_of_any_norm(const Eigen::Matrix<S, 4, 1>& theta) {
  const S s = S(2) / theta.squaredNorm();
  const S e0 = theta(0), e1 = theta(1), e2 = theta(2), e3 = theta(3);
  Eigen::Matrix<S, 3, 3> a;
  a << S(1) - s * (e2 * e2 + e3 * e3), s * (e1 * e2 - e0 * e3), s * (e1 * e3 + e0 * e2),
      s * (e1 * e2 + e0 * e3), S(1) - s * (e1 * e1 + e3 * e3), s * (e2 * e3 - e0 * e1),
      s * (e1 * e3 - e0 * e2), s * (e2 * e3 + e0 * e1), S(1) - s * (e1 * e1 + e2 * e2);
  return a;
}
/// Ḡ(θ) (body-frame velocity transformation).
inline Matrix34d g_bar_matrix(const EulerParameters& theta) {
  const double e0 = theta(0), e1 = theta(1), e2 = theta(2), e3 = theta(3);
  Matrix34d g;
  g << -e1, e0, e3, -e2,  //
      -e2, -e3, e0, e1,   //
      -e3, e2, -e1, e0;
  return g;
}
/// G(θ) (global-frame velocity transformation).
inline Matrix34d g_matrix(const EulerParameters& theta) {
  const double e0 = theta(0), e1 = theta(1), e2 = theta(2), e3 = theta(3);
  Matrix34d g;
  g << -e1, e0, -e3, e2,  //
      -e2, e3, e0, -e1,   //
      -e3, -e2, e1, e0;
  return g;
}

/// θ̇ = ½ θ ⊗ (0, ω̄_B) for a body-frame angular velocity.
inline EulerParameters euler_parameter_rate(const EulerParameters& theta,
                                            const Eigen::Vector3d& w_B) {
  // θ̇ = ½ θ ⊗ (0, ω̄)
  const double e0 = theta(0);
  const Eigen::Vector3d e = theta.tail<3>();
  EulerParameters rate;
  rate(0) = -0.5 * e.dot(w_B);
  rate.tail<3>() = 0.5 * (e0 * w_B + e.cross(w_B));
  return rate;
}

/// Unit quaternion of the rotation exp(φ̃): (cos(|φ|/2), sin(|φ|/2) φ/|φ|), in the scalar type
/// of φ (any Eigen expression of a 3-vector). sin(|φ|/2)/|φ| = ½ sinc(|φ|/2): in double a Taylor
/// series below |φ|/2 = 1e-2 (its first neglected term x⁶/5040 < 1e-16); another S takes the
/// quotient itself, exact to its own ε away from 0, and ½ φ at 0.
template <typename Derived>
Eigen::Matrix<typename Derived::Scalar, 4, 1> exp_quaternion(
    const Eigen::MatrixBase<Derived>& phi) {
  using S = typename Derived::Scalar;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const Eigen::Matrix<S, 3, 1> p = phi;
  const S angle = sqrt(p.squaredNorm());
  const S half = S(0.5) * angle;
  Eigen::Matrix<S, 4, 1> q;
  q(0) = cos(half);
  if constexpr (std::is_same_v<S, double>) {
    double s;
    if (half < 1e-2) {
      const double h2 = half * half;
      s = 0.5 * (1.0 - h2 / 6.0 + h2 * h2 / 120.0);
    } else {
      s = std::sin(half) / angle;
    }
    q.template tail<3>() = s * p;
  } else {
    q.template tail<3>() = angle > S(0) ? Eigen::Matrix<S, 3, 1>(sin(half) / angle * p)
                                        : Eigen::Matrix<S, 3, 1>(S(0.5) * p);
  }
  return q;
}
/// Rotation vector of a unit quaternion, |φ| ≤ π (the shortest of ±θ).
Eigen::Vector3d log_quaternion(const EulerParameters& theta);
/// Euler parameters of a rotation matrix (Shepperd's method), e0 ≥ 0.
EulerParameters euler_parameters_from_matrix(const Eigen::Matrix3d& rotation);

/// Geodesic angle |log(A(a)ᵀ A(b))| between two attitudes, in [0, π].
double geodesic_angle(const EulerParameters& a, const EulerParameters& b);

}  // namespace flexref::rotation
