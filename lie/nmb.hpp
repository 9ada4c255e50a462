#pragma once
/// \file nmb.hpp
/// NMB, the explicit Newmark scheme for rigid-body rotations of Krysl & Endres (2005)
/// (Newmark β = 0, γ = ½; docs/design/schemes.md), combined with central differences for the
/// translation of free bodies (the paper's hybrid step):
///   x_{n+1} = x_n + h v_n + ½ h² a_n
///   Θ = h W_n + ½ h² A_n,   R_{n+1} = R_n exp(Θ̃)
///   loads at the new configuration (one evaluation): f_{n+1}, T_{n+1} = R_{n+1}ᵀ Γ_{n+1}
///   v_{n+1} = v_n + ½ h (a_n + a_{n+1}),   a = f/m
///   solve J A + W(A) × J W(A) = T_{n+1},  W(A) = W_n + (h/2)(A_n + A)   (Newton, exact Jacobian)
///   W_{n+1} = W(A_{n+1})
/// Rotation about Br with I_Br (Br = centre of mass of a free body, the pivot of a pivot body).
///
/// Velocity-dependent loads are evaluated at the predicted velocities v_n + h a_n and
/// W_n + h A_n. A_0 solves the Euler equation at t0; at a step starting on a known load
/// discontinuity a_n and A_n are re-evaluated at t_n on the new segment (right limits).
///
/// The Newton iteration on A_{n+1} (per body; bodies are coupled only through T_{n+1}, which
/// is fixed during the solve) starts at A_n and stops when every component of f is
/// ≤ kNewtonTolerance (1e-14) times the size of the terms of f (scheme_support.hpp); the
/// correction computed from that last residual is applied too (it costs a 3×3 solve and no
/// evaluation, and keeps the remainder from biasing every step the same way). It takes 2–3
/// solves in the tests (book_toss, heavy_top, coulomb_wall); after kMaxNewtonIterations the
/// step fails and the state is kept.
#include <vector>

#include "lie/stepper.hpp"
#include "lie/wear_depth_update.hpp"

namespace flexref::lie {

class NmbStepper final : public Stepper {
 public:
  /// Quadratic convergence from the O(h) guess A_n reaches 1e-14 in ≤ 4 solves whenever the
  /// Jacobian is well conditioned; 10 leaves room for large h|W| and then gives up (measured:
  /// no root near A_n for h|W| ≳ 5 on an asymmetric body).
  static constexpr int kMaxNewtonIterations = 10;

  /// The model must outlive the stepper.
  explicit NmbStepper(const core::Model& model);

  std::string_view name() const override { return "nmb"; }
  int order() const override { return 2; }
  /// One per step, plus one at the first step and at each step starting on a discontinuity.
  double force_evaluations_per_step() const override { return 1.0; }

  void initialize(double t0, const core::State& state) override;
  StepStatus step(double h) override;

  double time() const override { return time_; }
  const core::State& state() const override { return state_; }
  /// Advances the contacts' worn depths (lie/wear_depth_update.hpp).
  bool integrates_wear_depth() const override { return true; }
  /// a_n (world) and A_n (body), the Newmark accelerations carried by the scheme.
  const core::Accelerations& accelerations() const { return acc_; }

  /// Newton iterations (Jacobian solves) summed over bodies and steps, and the most any one
  /// body needed in one step.
  long newton_iterations() const { return newton_iterations_; }
  int max_newton_iterations() const { return max_newton_iterations_; }
  long steps_taken() const { return steps_; }

 private:
  void restart(double h);

  const core::Model& model_;
  double time_ = 0.0;
  bool restart_pending_ = true;
  core::State state_;
  core::State next_;
  core::Accelerations acc_;       ///< a_n, A_n
  core::Accelerations acc_next_;  ///< a_{n+1}, A_{n+1}
  core::Workspace ws_;
  detail::WearDepthUpdate wear_;  ///< the worn depths' rates
  long newton_iterations_ = 0;
  int max_newton_iterations_ = 0;
  long steps_ = 0;
};

}  // namespace flexref::lie
