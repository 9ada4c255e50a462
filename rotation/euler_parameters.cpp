#include "rotation/euler_parameters.hpp"

#include <Eigen/Geometry>  // Vector3d::cross
#include <cmath>

#include "rotation/so3.hpp"

namespace flexref::rotation {

EulerParameters identity_euler_parameters() { return EulerParameters(1.0, 0.0, 0.0, 0.0); }

EulerParameters quaternion_multiply(const EulerParameters& p, const EulerParameters& q) {
  const double p0 = p(0);
  const double q0 = q(0);
  const Eigen::Vector3d pv = p.tail<3>();
  const Eigen::Vector3d qv = q.tail<3>();
  EulerParameters r;
  r(0) = p0 * q0 - pv.dot(qv);
  r.tail<3>() = p0 * qv + q0 * pv + pv.cross(qv);
  return r;
}

EulerParameters quaternion_conjugate(const EulerParameters& q) {
  return EulerParameters(q(0), -q(1), -q(2), -q(3));
}

Eigen::Matrix3d rotation_matrix(const EulerParameters& theta) {
  // A = (2e0² − 1) I + 2 (e eᵀ + e0 ẽ), written out entry by entry (this is on every
  // evaluation's path).
  const double e0 = theta(0), e1 = theta(1), e2 = theta(2), e3 = theta(3);
  const double d = 2.0 * e0 * e0 - 1.0;
  Eigen::Matrix3d a;
  a << d + 2.0 * e1 * e1, 2.0 * (e1 * e2 - e0 * e3), 2.0 * (e1 * e3 + e0 * e2),  //
      2.0 * (e1 * e2 + e0 * e3), d + 2.0 * e2 * e2, 2.0 * (e2 * e3 - e0 * e1),   //
      2.0 * (e1 * e3 - e0 * e2), 2.0 * (e2 * e3 + e0 * e1), d + 2.0 * e3 * e3;
  return a;
}

Matrix34d g_bar_matrix(const EulerParameters& theta) {
  const double e0 = theta(0), e1 = theta(1), e2 = theta(2), e3 = theta(3);
  Matrix34d g;
  g << -e1, e0, e3, -e2,  //
      -e2, -e3, e0, e1,   //
      -e3, e2, -e1, e0;
  return g;
}

Matrix34d g_matrix(const EulerParameters& theta) {
  const double e0 = theta(0), e1 = theta(1), e2 = theta(2), e3 = theta(3);
  Matrix34d g;
  g << -e1, e0, -e3, e2,  //
      -e2, e3, e0, -e1,   //
      -e3, -e2, e1, e0;
  return g;
}

EulerParameters euler_parameter_rate(const EulerParameters& theta, const Eigen::Vector3d& w_B) {
  // θ̇ = ½ θ ⊗ (0, ω̄)
  const double e0 = theta(0);
  const Eigen::Vector3d e = theta.tail<3>();
  EulerParameters rate;
  rate(0) = -0.5 * e.dot(w_B);
  rate.tail<3>() = 0.5 * (e0 * w_B + e.cross(w_B));
  return rate;
}

EulerParameters exp_quaternion(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const double half = 0.5 * angle;
  // sin(|φ|/2)/|φ| = ½ sinc(|φ|/2); Taylor below 1e-2 (first neglected term ~ x⁶/5040 < 1e-16).
  double s;
  if (half < 1e-2) {
    const double h2 = half * half;
    s = 0.5 * (1.0 - h2 / 6.0 + h2 * h2 / 120.0);
  } else {
    s = std::sin(half) / angle;
  }
  EulerParameters q;
  q(0) = std::cos(half);
  q.tail<3>() = s * phi;
  return q;
}

Eigen::Vector3d log_quaternion(const EulerParameters& theta) {
  EulerParameters q = theta;
  if (q(0) < 0.0) q = -q;
  const Eigen::Vector3d e = q.tail<3>();
  const double sin_half = e.norm();
  if (sin_half < 1e-300) return 2.0 * e;
  const double half_angle = std::atan2(sin_half, q(0));
  return (2.0 * half_angle / sin_half) * e;
}

EulerParameters euler_parameters_from_matrix(const Eigen::Matrix3d& rotation) {
  // Shepperd (J. Guidance 1(3), 1978): the largest of 4e0² = 1 + tr A, 4ei² = 1 + 2Aii − tr A
  // comes from the diagonal without cancellation, the other three from off-diagonal sums and
  // differences divided by it. (Going through exp_quaternion(log_so3(A)) instead gave
  // e0 = −1.6e-16 at |φ| = π, where the rounded |φ| slightly exceeds π.)
  const Eigen::Matrix3d& a = rotation;
  const double trace = a.trace();
  EulerParameters q;
  if (trace > a(0, 0) && trace > a(1, 1) && trace > a(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + trace);  // 4 e0
    q << 0.25 * s, (a(2, 1) - a(1, 2)) / s, (a(0, 2) - a(2, 0)) / s, (a(1, 0) - a(0, 1)) / s;
  } else if (a(0, 0) > a(1, 1) && a(0, 0) > a(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + a(0, 0) - a(1, 1) - a(2, 2));  // 4 e1
    q << (a(2, 1) - a(1, 2)) / s, 0.25 * s, (a(0, 1) + a(1, 0)) / s, (a(0, 2) + a(2, 0)) / s;
  } else if (a(1, 1) > a(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + a(1, 1) - a(0, 0) - a(2, 2));  // 4 e2
    q << (a(0, 2) - a(2, 0)) / s, (a(0, 1) + a(1, 0)) / s, 0.25 * s, (a(1, 2) + a(2, 1)) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + a(2, 2) - a(0, 0) - a(1, 1));  // 4 e3
    q << (a(1, 0) - a(0, 1)) / s, (a(0, 2) + a(2, 0)) / s, (a(1, 2) + a(2, 1)) / s, 0.25 * s;
  }
  if (q(0) < 0.0) q = -q;  // θ and −θ give the same A; the convention is e0 ≥ 0
  return q / q.norm();
}

double geodesic_angle(const EulerParameters& a, const EulerParameters& b) {
  // |log(A(a)ᵀ A(b))| = 2 atan2(|vec(a* ⊗ b)|, |scalar(a* ⊗ b)|), accurate at 0 and π.
  const EulerParameters d = quaternion_multiply(quaternion_conjugate(a), b);
  return 2.0 * std::atan2(d.tail<3>().norm(), std::abs(d(0)));
}

}  // namespace flexref::rotation
