#pragma once
/// \file c1.hpp
/// ALGO C1 of Simo & Wong (1991), implicit (Newmark β = ½, γ = 1; docs/design/schemes.md),
/// combined with central differences for the translation of free bodies (the paper's hybrid
/// step). Per step:
///   x_{n+1} = x_n + h v_n + ½ h² a_n                                   (explicit)
///   Θ = (h/2)(W_n + W_{n+1}),   R_{n+1} = R_n exp(Θ̃)
///   R_{n+1} J W_{n+1} − R_n J W_n = h Γ_{n+½}                          (3 unknowns per body)
///   Γ_{n+½} at t_{n+½} and the midpoint configuration R_n exp(Θ̃/2), ½(x_n + x_{n+1})
///   a_{n+1} = f_{n+1}/m at the new configuration,  v_{n+1} = v_n + ½ h (a_n + a_{n+1})
///   A_{n+1} = (W_{n+1} − W_n)/h   (kept as the Newton predictor W_n + h A_n)
/// Torque-free, it conserves π = R J W and the kinetic energy exactly (to the Newton
/// tolerance and round-off).
///
/// Solution of the implicit equations: one block Newton over all bodies at once. The unknowns
/// are W_{n+1} of every body; each iteration evaluates the loads of all bodies once, at the
/// midpoint configuration of the current iterate, and updates every body with its own 3×3
/// matrix ∂r/∂W = J − (h/2) (exp(−Θ̃) b)~ J_r(Θ), b = J W_n + h R_nᵀ Γ_{n+½} (c1_newton.hpp).
/// That matrix is the exact Jacobian of the inertial part and of a global torque held fixed
/// (the rotation R_{n+1}ᵀ applied to it is differentiated); the dependence of the loads on the
/// configuration and the coupling between bodies through the loads are left out (quasi-Newton,
/// no extra evaluations): the iteration converges quadratically for a torque fixed in space
/// and linearly otherwise, with contraction ≈ (h²/4)|∂Γ/∂Θ|/|J| per iteration (≈ 1e-4 for the
/// heavy top at h = 1e-3). Converged when every residual component is ≤ kNewtonTolerance
/// (1e-14) times the size of the terms J W_{n+1}, J W_n and h R_nᵀ Γ (scheme_support.hpp);
/// the correction computed from that last residual is applied as well (no evaluation; without
/// it the ≤ 1e-14 remainder biased every step alike and the energy of free_spin drifted by
/// 1.4e-10 over 1e4 steps, with it 3e-14). Far from the root (h|W| ≳ 1) a step that does not
/// decrease Σ|r|² is halved (backtracking, ≥ 1/64), each trial costing one evaluation.
/// Measured: 2 solves per step on free_spin and book_toss at small h, ≤ 4 on heavy_top at
/// h = 1e-3 and coulomb_wall at h = 5e-3; converges for h|W| ≤ 1.5, fails (reported) from ≈ 2.
///
/// Velocity-dependent loads see W_{n+½} = ½(W_n + W_{n+1}) of the iterate and the predicted
/// v_n + ½ h a_n at the midpoint; at the end evaluation W_{n+1} and the predicted v_n + h a_n.
#include <Eigen/Core>
#include <vector>

#include "lie/stepper.hpp"
#include "lie/wear_depth_update.hpp"

namespace flexref::lie {

class C1Stepper final : public Stepper {
 public:
  /// Residual (= force) evaluations allowed in one step. Quadratic convergence from the O(h²)
  /// predictor needs 2–3; linear convergence with a contraction ≤ 0.2 needs ≤ 20 to gain 14
  /// digits; beyond 30 (backtracking included) the step fails.
  static constexpr int kMaxNewtonEvaluations = 30;
  /// Shortest backtracking step (α = 1/64) before a non-decreasing step is taken anyway.
  static constexpr double kMinStepLength = 1.0 / 64.0;

  /// The model must outlive the stepper.
  explicit C1Stepper(const core::Model& model);

  std::string_view name() const override { return "c1"; }
  int order() const override { return 2; }
  /// Mean over the steps taken since initialize (before the first step, the least possible:
  /// one Newton evaluation, plus the end-of-step evaluation when a body translates).
  double force_evaluations_per_step() const override;

  void initialize(double t0, const core::State& state) override;
  StepStatus step(double h) override;

  double time() const override { return time_; }
  const core::State& state() const override { return state_; }
  /// Advances the contacts' worn depths (lie/wear_depth_update.hpp).
  bool integrates_wear_depth() const override { return true; }
  /// a_n (world) and A_n = (W_n − W_{n−1})/h (body); A_0 from the Euler equation.
  const core::Accelerations& accelerations() const { return acc_; }

  /// Newton iterations (Jacobian solves) summed over steps, the most in one step, and the
  /// force evaluations (one per residual, plus the end-of-step and restart evaluations).
  long newton_iterations() const { return newton_iterations_; }
  int max_newton_iterations() const { return max_newton_iterations_; }
  long force_evaluations() const { return evaluations_; }
  long steps_taken() const { return steps_; }

 private:
  struct NewtonOutcome {
    bool converged = false;
    bool finite = true;
    int iterations = 0;  ///< Jacobian solves
    double relative_residual = 0.0;
    int worst_body = 0;
  };
  void restart(double h);
  /// Newton on W_{n+1} (in next_), from the predictor already in next_.
  NewtonOutcome solve_balance(double t_n, double h);
  /// Adds the loads' dependence on W_{n+1} to every body's Jacobian (forward differences, three
  /// evaluations per body), for models with velocity-dependent loads.
  void add_load_jacobian(double t_n, double h);

  const core::Model& model_;
  bool has_free_body_ = false;  ///< a free or flexible body: evaluate again at t_{n+1}
  double time_ = 0.0;
  bool restart_pending_ = true;
  core::State state_;
  core::State next_;  ///< step n + 1; its W is the Newton iterate
  core::State mid_;   ///< midpoint configuration where Γ_{n+½} is evaluated
  core::Accelerations acc_;
  core::Accelerations acc_next_;
  std::vector<Eigen::Matrix3d> R_n_transpose_;  ///< R_nᵀ per body
  std::vector<Eigen::Vector3d> b_;              ///< J W_n + h R_nᵀ Γ_{n+½} per body
  std::vector<Eigen::Vector3d> residual_;       ///< r(W) per body
  std::vector<Eigen::Matrix3d> jacobian_;       ///< ∂r/∂W per body
  std::vector<Eigen::Vector3d> w_accepted_;     ///< last accepted Newton iterate per body
  std::vector<Eigen::Vector3d> delta_;          ///< its Newton correction per body
  core::Workspace ws_;
  detail::WearDepthUpdate wear_;  ///< the worn depths' rates
  long newton_iterations_ = 0;
  int max_newton_iterations_ = 0;
  long evaluations_ = 0;
  long steps_ = 0;
};

}  // namespace flexref::lie
