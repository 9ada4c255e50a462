#pragma once
/// \file nmb_newton.hpp
/// The Euler equation NMB solves for A_{n+1} (Krysl & Endres 2005, explicit Newmark β = 0,
/// γ = ½; docs/design/schemes.md) and its exact Jacobian, exposed for finite-difference tests:
///   f(A) = J A + W(A) × J W(A) − T_{n+1},   W(A) = W_n + (h/2)(A_n + A)
///   ∂f/∂A = J + (h/2) (W̃ J − (J W)~)
/// (d(W × JW) = dW × JW + W × J dW = −(JW)~ dW + W̃ J dW, and dW = (h/2) dA).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rotation/so3.hpp"

namespace flexref::lie::detail {

/// W(A) = W_n + (h/2)(A_n + A): the trapezoidal velocity update (γ = ½).
inline Eigen::Vector3d nmb_velocity(const Eigen::Vector3d& w_n, const Eigen::Vector3d& alpha_n,
                                    const Eigen::Vector3d& alpha, double h) {
  return w_n + (0.5 * h) * (alpha_n + alpha);
}

/// The residual, its Newton matrix and the size of its terms at one iterate.
struct NmbLinearization {
  Eigen::Vector3d residual;  ///< f(A) = J A + W × J W − T
  Eigen::Matrix3d jacobian;  ///< ∂f/∂A = J + (h/2)(W̃ J − (J W)~)
  /// |J A| + |W| |J W| + |T| (max norms): f's round-off is ε times this (W × J W is rounded
  /// relative to |W| |J W|, not to its own size).
  double scale = 0.0;
};

// Inlined into the Newton loop: a call returning the struct through memory costs NMB ~12 % of
// its step (bench/scheme_step_benchmark, docs/performance.md "Build").
[[gnu::always_inline]] inline NmbLinearization nmb_linearize(
    const Eigen::Matrix3d& J, const Eigen::Vector3d& torque_B, const Eigen::Vector3d& w_n,
    const Eigen::Vector3d& alpha_n, const Eigen::Vector3d& alpha, double h) {
  const Eigen::Vector3d w = nmb_velocity(w_n, alpha_n, alpha, h);
  const Eigen::Vector3d J_w = J * w;
  const Eigen::Vector3d J_alpha = J * alpha;
  return {J_alpha + w.cross(J_w) - torque_B,
          J + (0.5 * h) * (rotation::hat(w) * J - rotation::hat(J_w)),
          J_alpha.cwiseAbs().maxCoeff() + w.cwiseAbs().maxCoeff() * J_w.cwiseAbs().maxCoeff() +
              torque_B.cwiseAbs().maxCoeff()};
}

}  // namespace flexref::lie::detail
