#pragma once
/// \file nmb_newton.hpp
/// The Euler equation NMB solves for A_{n+1} (Krysl & Endres 2005, explicit Newmark β = 0,
/// γ = ½; design/schemes.md) and its exact Jacobian, exposed for finite-difference tests:
///   f(A) = J A + W(A) × J W(A) − T_{n+1},   W(A) = W_n + (h/2)(A_n + A)
///   ∂f/∂A = J + (h/2) (W̃ J − (J W)~)
/// (d(W × JW) = dW × JW + W × J dW = −(JW)~ dW + W̃ J dW, and dW = (h/2) dA).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/so3.hpp"

namespace flexref::lie::detail {

/// W(A) = W_n + (h/2)(A_n + A): the trapezoidal velocity update (γ = ½).
inline Eigen::Vector3d nmb_velocity(const Eigen::Vector3d& w_n, const Eigen::Vector3d& alpha_n,
                                    const Eigen::Vector3d& alpha, double h) {
  return w_n + 0.5 * h * (alpha_n + alpha);
}

/// f(A) = J A + W(A) × J W(A) − T.
inline Eigen::Vector3d nmb_residual(const Eigen::Matrix3d& J, const Eigen::Vector3d& torque_B,
                                    const Eigen::Vector3d& w_n, const Eigen::Vector3d& alpha_n,
                                    const Eigen::Vector3d& alpha, double h) {
  const Eigen::Vector3d w = nmb_velocity(w_n, alpha_n, alpha, h);
  return J * alpha + w.cross(J * w) - torque_B;
}

/// ∂f/∂A = J + (h/2)(W̃ J − (J W)~) at W = W(A).
inline Eigen::Matrix3d nmb_jacobian(const Eigen::Matrix3d& J, const Eigen::Vector3d& w_n,
                                    const Eigen::Vector3d& alpha_n, const Eigen::Vector3d& alpha,
                                    double h) {
  const Eigen::Vector3d w = nmb_velocity(w_n, alpha_n, alpha, h);
  return J + 0.5 * h * (core::hat(w) * J - core::hat(J * w));
}

}  // namespace flexref::lie::detail
