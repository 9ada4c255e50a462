#include "rotation/euler_parameters.hpp"

#include <Eigen/Geometry>  // Vector3d::cross
#include <cmath>

#include "rotation/so3.hpp"

namespace flexref::rotation {

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
