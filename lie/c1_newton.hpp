#pragma once
/// \file c1_newton.hpp
/// The nonlinear equation of one C1 step for one body and its Jacobian (Simo & Wong 1991,
/// ALGO C1; docs/design/schemes.md), exposed so that tests can check the Jacobian against finite
/// differences. With the global torque Γ_{n+½} held fixed, the balance of angular momentum
///   R_{n+1} J W_{n+1} − R_n J W_n = h Γ_{n+½},   R_{n+1} = R_n exp(Θ̃),  Θ = (h/2)(W_n + W_{n+1})
/// is, premultiplied by R_{n+1}ᵀ = exp(−Θ̃) R_nᵀ,
///   r(W) = J W − exp(−Θ̃) b = 0,   b = J W_n + h R_nᵀ Γ_{n+½}   (body frame of step n).
#include <Eigen/Core>

#include "rotation/so3.hpp"

namespace flexref::lie::detail {

/// Θ = (h/2)(W_n + W): the incremental rotation vector of C1 (Newmark β = ½, γ = 1).
inline Eigen::Vector3d c1_increment(const Eigen::Vector3d& w_n, const Eigen::Vector3d& w,
                                    double h) {
  return 0.5 * h * (w_n + w);
}

/// \f[ \frac{\partial}{\partial\Theta}\bigl(e^{-\tilde\Theta} b\bigr)
///     = \bigl(e^{-\tilde\Theta} b\bigr)^\sim \, J_r(\Theta) \f]
/// Derivation: exp((Θ + δ)~) = exp(Θ̃) exp((J_r(Θ) δ)~) + O(δ²) with the right Jacobian
/// J_r(Θ) = dexp_{−Θ} (rotation/so3.hpp); transposing, exp(−(Θ + δ)~) = (I − (J_r δ)~) exp(−Θ̃),
/// so δ(exp(−Θ̃) b) = −(J_r δ) × exp(−Θ̃) b = (exp(−Θ̃) b)~ J_r δ.
inline Eigen::Matrix3d d_rotated_by_minus_theta(const Eigen::Vector3d& b,
                                                const Eigen::Vector3d& theta) {
  const Eigen::Vector3d rotated = rotation::exp_so3(theta).transpose() * b;
  return rotation::hat(rotated) * rotation::right_jacobian(theta);
}

/// The residual and its Newton matrix at one iterate.
struct C1Linearization {
  Eigen::Vector3d residual;  ///< r(W) = J W − exp(−Θ̃) b
  /// ∂r/∂W = J − (h/2) (exp(−Θ̃) b)~ J_r(Θ): exact for a fixed b, i.e. for a global torque
  /// that does not depend on the configuration (C1 uses it as a quasi-Newton matrix otherwise).
  Eigen::Matrix3d jacobian;
};

inline C1Linearization c1_linearize(const Eigen::Matrix3d& J, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& w_n, const Eigen::Vector3d& w,
                                    double h) {
  const Eigen::Vector3d theta = c1_increment(w_n, w, h);
  const Eigen::Vector3d rotated_b = rotation::exp_so3(theta).transpose() * b;  // exp(−Θ̃) b
  return {J * w - rotated_b,
          J - (0.5 * h) * (rotation::hat(rotated_b) * rotation::right_jacobian(theta))};
}

}  // namespace flexref::lie::detail
