#include "rotation/so3.hpp"

#include <cmath>

namespace flexref::rotation {
namespace {

// Below this angle the closed forms lose accuracy to cancellation; the Taylor series used
// instead are truncated after the x⁴ term, whose successor (x⁶/5040 for sinc, smaller for the
// others) is below 1e-16 · coefficient for x < 1e-2.
constexpr double kSmallAngle = 1e-2;

// sin(x)/x
double sinc(double x) {
  const double x2 = x * x;
  if (x < kSmallAngle) return 1.0 - x2 / 6.0 + x2 * x2 / 120.0;
  return std::sin(x) / x;
}
// (1 − cos x)/x² = ½ (sin(x/2)/(x/2))². The half-angle form has no cancellation: computing
// 1 − cos x directly loses ε/x² relative (≈1e-12 just above kSmallAngle, 20 ulp in dexp).
double one_minus_cos_over_x2(double x) {
  const double x2 = x * x;
  if (x < kSmallAngle) return 0.5 - x2 / 24.0 + x2 * x2 / 720.0;
  const double half = 0.5 * x;
  const double sinc_half = std::sin(half) / half;
  return 0.5 * sinc_half * sinc_half;
}
// (x − sin x)/x³
double x_minus_sin_over_x3(double x) {
  const double x2 = x * x;
  if (x < kSmallAngle) return 1.0 / 6.0 - x2 / 120.0 + x2 * x2 / 5040.0;
  return (x - std::sin(x)) / (x2 * x);
}
// (1 − (x/2) cot(x/2)) / x²
double dexp_inv_coefficient(double x) {
  const double x2 = x * x;
  if (x < kSmallAngle) return 1.0 / 12.0 + x2 / 720.0 + x2 * x2 / 30240.0;
  const double half = 0.5 * x;
  return (1.0 - half * std::cos(half) / std::sin(half)) / x2;
}

}  // namespace

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const Eigen::Matrix3d phi_hat = hat(phi);
  return Eigen::Matrix3d::Identity() + sinc(angle) * phi_hat +
         one_minus_cos_over_x2(angle) * phi_hat * phi_hat;
}

Eigen::Vector3d log_so3(const Eigen::Matrix3d& rotation) {
  // Through the unit quaternion: atan2 is accurate over the whole range, including near 0
  // (where acos((tr R − 1)/2) loses half the digits) and near π (where sin θ → 0).
  const double trace = rotation.trace();
  Eigen::Vector4d q;  // (w, x, y, z), Shepperd's method picks the largest component
  if (trace > rotation(0, 0) && trace > rotation(1, 1) && trace > rotation(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    q << 0.25 * s, (rotation(2, 1) - rotation(1, 2)) / s, (rotation(0, 2) - rotation(2, 0)) / s,
        (rotation(1, 0) - rotation(0, 1)) / s;
  } else if (rotation(0, 0) > rotation(1, 1) && rotation(0, 0) > rotation(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + rotation(0, 0) - rotation(1, 1) - rotation(2, 2));
    q << (rotation(2, 1) - rotation(1, 2)) / s, 0.25 * s, (rotation(0, 1) + rotation(1, 0)) / s,
        (rotation(0, 2) + rotation(2, 0)) / s;
  } else if (rotation(1, 1) > rotation(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + rotation(1, 1) - rotation(0, 0) - rotation(2, 2));
    q << (rotation(0, 2) - rotation(2, 0)) / s, (rotation(0, 1) + rotation(1, 0)) / s, 0.25 * s,
        (rotation(1, 2) + rotation(2, 1)) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + rotation(2, 2) - rotation(0, 0) - rotation(1, 1));
    q << (rotation(1, 0) - rotation(0, 1)) / s, (rotation(0, 2) + rotation(2, 0)) / s,
        (rotation(1, 2) + rotation(2, 1)) / s, 0.25 * s;
  }
  if (q(0) < 0.0) q = -q;
  const Eigen::Vector3d e = q.tail<3>();
  const double sin_half = e.norm();
  const double half_angle = std::atan2(sin_half, q(0));
  // φ = 2 (θ/2)/sin(θ/2) e; (θ/2)/sin(θ/2) → 1 as θ → 0.
  if (sin_half < 1e-300) return 2.0 * e;
  return (2.0 * half_angle / sin_half) * e;
}

Eigen::Matrix3d dexp(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const Eigen::Matrix3d phi_hat = hat(phi);
  return Eigen::Matrix3d::Identity() + one_minus_cos_over_x2(angle) * phi_hat +
         x_minus_sin_over_x3(angle) * phi_hat * phi_hat;
}

Eigen::Matrix3d dexp_inv(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const Eigen::Matrix3d phi_hat = hat(phi);
  return Eigen::Matrix3d::Identity() - 0.5 * phi_hat +
         dexp_inv_coefficient(angle) * phi_hat * phi_hat;
}

Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& phi) { return dexp(-phi); }

Eigen::Matrix3d right_jacobian_inv(const Eigen::Vector3d& phi) { return dexp_inv(-phi); }

}  // namespace flexref::rotation
