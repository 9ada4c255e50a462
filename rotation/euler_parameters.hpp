#pragma once
/// \file euler_parameters.hpp
/// Euler parameters θ = (e0, e1, e2, e3), scalar first, θᵀθ = 1, describing the rotation
/// body → global (docs/design/model.md, Shabana "Dynamics of multibody systems" §2.7):
///   A  = (2e0² − 1) I + 2 (e eᵀ + e0 ẽ)
///   Ḡ  = [−e  e0 I − ẽ],  G = [−e  e0 I + ẽ],  A = G Ḡᵀ
///   ω̄  = 2 Ḡ θ̇,  ω = 2 G θ̇,  θ̇ = ½ Ḡᵀ ω̄ = ½ θ ⊗ (0, ω̄)
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace flexref::rotation {

using EulerParameters = Eigen::Vector4d;  ///< (e0, e1, e2, e3), scalar first
using Matrix34d = Eigen::Matrix<double, 3, 4>;

EulerParameters identity_euler_parameters();
/// Hamilton product p ⊗ q (scalar first); rotation of q followed by p in the body→global sense.
EulerParameters quaternion_multiply(const EulerParameters& p, const EulerParameters& q);
EulerParameters quaternion_conjugate(const EulerParameters& q);

/// A(θ), body → global (exact rotation for unit θ).
Eigen::Matrix3d rotation_matrix(const EulerParameters& theta);
/// Ḡ(θ) (body-frame velocity transformation).
Matrix34d g_bar_matrix(const EulerParameters& theta);
/// G(θ) (global-frame velocity transformation).
Matrix34d g_matrix(const EulerParameters& theta);

/// θ̇ = ½ θ ⊗ (0, ω̄_B) for a body-frame angular velocity.
EulerParameters euler_parameter_rate(const EulerParameters& theta, const Eigen::Vector3d& w_B);

/// Unit quaternion of the rotation exp(φ̃): (cos(|φ|/2), sin(|φ|/2) φ/|φ|).
EulerParameters exp_quaternion(const Eigen::Vector3d& phi);
/// Rotation vector of a unit quaternion, |φ| ≤ π (the shortest of ±θ).
Eigen::Vector3d log_quaternion(const EulerParameters& theta);
/// Euler parameters of a rotation matrix (Shepperd's method), e0 ≥ 0.
EulerParameters euler_parameters_from_matrix(const Eigen::Matrix3d& rotation);

/// Geodesic angle |log(A(a)ᵀ A(b))| between two attitudes, in [0, π].
double geodesic_angle(const EulerParameters& a, const EulerParameters& b);

}  // namespace flexref::rotation
