#pragma once
/// \file so3.hpp
/// The rotation group SO(3): hat/vee, exponential and logarithm, and the differential of the
/// exponential (dexp) with its inverse. Conventions follow Iserles et al. (Lie-group methods,
/// Acta Numerica 2000) and Bullo & Murray (1995):
///   exp(φ̃) = I + sin|φ|/|φ| φ̃ + (1 − cos|φ|)/|φ|² φ̃²                      (Rodrigues)
///   d/dt exp(φ̃) = (dexp_φ φ̇)~ exp(φ̃)    (left trivialization, "dexp")
///   d/dt exp(φ̃) = exp(φ̃) (dexp_{−φ} φ̇)~ (right trivialization, the body-frame tangent
///   operator T(φ) of Simo & Wong 1991 and Brüls & Cardona 2010)
/// Small-angle branches switch to Taylor series below kSmallAngle, where the first neglected
/// term is below machine epsilon (see so3.cpp).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace flexref::rotation {

/// ã with ã b = a × b.
inline Eigen::Matrix3d hat(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0.0, -a.z(), a.y(),  //
      a.z(), 0.0, -a.x(),   //
      -a.y(), a.x(), 0.0;
  return m;
}
/// Inverse of hat on skew-symmetric matrices (the skew part of any matrix).
inline Eigen::Vector3d vee(const Eigen::Matrix3d& m) {
  return 0.5 * Eigen::Vector3d(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
}

/// Rotation matrix exp(φ̃) (Rodrigues' formula).
Eigen::Matrix3d exp_so3(const Eigen::Vector3d& phi);
/// Rotation vector φ with exp(φ̃) = R and |φ| ≤ π; robust near π.
Eigen::Vector3d log_so3(const Eigen::Matrix3d& rotation);

/// \f[ \mathrm{dexp}_\varphi = I + \frac{1-\cos|\varphi|}{|\varphi|^2}\tilde\varphi
///     + \frac{|\varphi|-\sin|\varphi|}{|\varphi|^3}\tilde\varphi^2 \f]  (left Jacobian).
Eigen::Matrix3d dexp(const Eigen::Vector3d& phi);
/// \f[ \mathrm{dexp}^{-1}_\varphi = I - \tfrac12\tilde\varphi
///     +
///     \frac{1}{|\varphi|^2}\Bigl(1-\frac{|\varphi|}{2}\cot\frac{|\varphi|}{2}\Bigr)\tilde\varphi^2
///     \f]
Eigen::Matrix3d dexp_inv(const Eigen::Vector3d& phi);
/// Right Jacobian (body-frame tangent operator T(φ)) = dexp_{−φ} = dexp_φᵀ.
Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& phi);
/// Inverse of the right Jacobian = dexp_inv_{−φ}.
Eigen::Matrix3d right_jacobian_inv(const Eigen::Vector3d& phi);

}  // namespace flexref::rotation
