#pragma once
/// \file genalpha.hpp
/// The Lie-group generalized-α scheme of Brüls, Cardona & Arnold (Mechanism and Machine Theory
/// 48, 2012) on SO(3) × R³ per body (× Rⁿ for the modes of a flexible body, LTE or coupled), the
/// comparison method of the field (docs/schemes.md,
/// "Lie-group generalized-α"). Per step (lie/genalpha_newton.hpp has the equations):
///   q_{n+1} = q_n ∘ exp(h Δq_n),  Δq_n = v_n + (½ − β) h a_n + β h a_{n+1}
///   v_{n+1} = v_n + (1 − γ) h a_n + γ h a_{n+1}
///   (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) v̇_{n+1} + α_f v̇_n
/// with v̇_{n+1} from the equations of motion at t_{n+1} (every force element through the model)
/// and, for ideal joints, Φ(q_{n+1}) = 0 with multipliers (index 3, scaled). Coefficients from
/// ρ∞ (lie/genalpha_parameters.hpp). Initial accelerations from the equations at t0: a_0 = v̇_0.
///
/// Newton on all unknowns at once (x per body, λ̂ per independent joint row) with the iteration
/// matrix S of genalpha_newton.hpp, sparse (the bodies' coupling), LU-factored by KLU
/// (lie/sparse_lu.hpp: ordered once per set of rows in force, refactored with the same pivots
/// while they hold), and kept across iterations and steps of the
/// same length while the residual contracts by kSlowContraction or better per iteration
/// (modified Newton); reassembled at the current iterate when it does not, and after a restart
/// or a change of h. A correction computed with a matrix assembled at its own iterate is a
/// descent direction of ‖r‖² (its directional derivative is −2‖r‖²); where the full correction
/// does not decrease ‖r‖² enough (kArmijo) it is halved (a backtracking line search): the
/// Newton iteration then follows the residual down instead of cycling across a contact's onset
/// or a regularized friction's steep slope, where the linear model holds over less than a full
/// correction. Assembly costs 6 evaluations per colour of bodies (genalpha_newton.hpp; 18 on a
/// chain) and a sparse factorization, an iteration one evaluation and a sparse solve. Converged
/// when every component is ≤ kNewtonTolerance (1e-14) of the size of its terms, or at the round-off
/// floor (newton_stagnated); the last correction is applied as well. At a known load discontinuity
/// v̇_n is re-evaluated on the new branch (its right limit) and a_n kept: bodies whose loads do
/// not jump step exactly as they would alone.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "lie/genalpha_newton.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/sparse_lu.hpp"
#include "lie/stepper.hpp"
#include "lie/wear_depth_update.hpp"

namespace flexref::lie {

class GenAlphaStepper final : public Stepper {
 public:
  /// Newton iterations allowed in one step (modified Newton with a contraction ≤ ½ gains 14
  /// digits in ≤ 47 iterations at worst, quadratic-like contraction in 3–5; reassembling the
  /// matrix restores fast contraction).
  static constexpr int kMaxNewtonIterations = 30;
  /// Residual ratio between iterations above which the matrix is assembled anew: a contraction
  /// of ¼ gains 14 digits in ≤ 24 iterations, a fresh matrix in 2–4 on smooth problems.
  static constexpr double kSlowContraction = 0.25;
  /// Largest relative residual accepted when it repeats exactly between two iterations (the
  /// round-off floor of a residual whose terms cancel; 1e-8 is below the truncation error of
  /// any step a study uses, as kNewtonStagnationFloor's 1e-10 is for the others).
  static constexpr double kRepeatedResidualFloor = 1e-8;
  /// Reassemblies of the iteration matrix allowed in one step beyond the first.
  static constexpr int kMaxReassemblies = 4;
  /// Halvings of a correction allowed in one step (the line search: a fraction 2⁻¹⁰ of a
  /// correction that still raises the residual is no longer a Newton step worth following).
  static constexpr int kMaxBacktracks = 10;
  /// Sufficient decrease of the line search (Armijo): ‖r(z − s Δz)‖² ≤ (1 − 2 c s) ‖r(z)‖², with
  /// c = 1e-4 (Dennis & Schnabel's choice, "Numerical Methods for Unconstrained Optimization",
  /// §6.3: any decrease a small multiple of the one the linear model predicts).
  static constexpr double kArmijo = 1e-4;

  /// The model must outlive the stepper.
  GenAlphaStepper(const core::Model& model, const GenAlphaParameters& parameters);

  std::string_view name() const override { return "genalpha"; }
  int order() const override { return 2; }
  /// Mean over the steps taken (before the first step: one residual and one matrix assembly).
  double force_evaluations_per_step() const override;

  void initialize(double t0, const core::State& state) override;
  StepStatus step(double h) override;
  /// initialize, then a_0 = a0 (stacked as accelerations()) instead of v̇_0: the one-step map of the
  /// scheme's full state (q, v, a) — its amplification matrix on a linear oscillator, tests.
  void initialize_with_auxiliary(double t0, const core::State& state, const Eigen::VectorXd& a0);

  double time() const override { return time_; }
  const core::State& state() const override { return state_; }
  /// Advances the contacts' worn depths (lie/wear_depth_update.hpp).
  bool integrates_wear_depth() const override { return true; }
  const GenAlphaParameters& parameters() const { return system_.parameters(); }
  /// v̇_n (stacked: per body a_WBr, α̅, q̈_f) and the auxiliary a_n.
  const Eigen::VectorXd& accelerations() const { return vdot_; }
  const Eigen::VectorXd& auxiliary_accelerations() const { return a_; }
  /// The multipliers λ_n of the independent joint rows (M v̇ + Jᵀ λ = Q), and the rows they
  /// belong to (the model's independent rows at the start, chosen again in motion where they
  /// become dependent among themselves: track_joints).
  Eigen::VectorXd multipliers() const;
  const std::vector<int>& multiplier_rows() const { return system_.active_rows(); }

  long newton_iterations() const { return newton_iterations_; }
  int max_newton_iterations() const { return max_newton_iterations_; }
  long steps_taken() const { return steps_; }

 private:
  /// v̇_n (and λ_n) from the equations at t_n; a_0 = v̇_0 at the first call after initialize.
  void restart();
  /// a_0 = v̇(t_0 + (α_m − α_f) h) (GenAlphaParameters::perturbed_start); segment: the branch.
  void perturbed_start(double segment);
  /// The joints at an accepted state (t, next): a singular configuration reached or passed since
  /// the last accepted one (Model::advance_tracker: the rank and orientation tests of
  /// core/constrained_solve_tpl.hpp on tracker_'s rows and accepted state) is the failure's
  /// message; rows the tracker chose again (they became dependent among themselves) become the
  /// Newton system's, λ̂ carried over to them (ConstraintTracker::carry). Returns "" when the
  /// step may be accepted.
  std::string track_joints(double t, const core::State& next);
  /// The failure message of a step whose Newton iteration did not converge: with joints, a
  /// singular configuration ahead (Model::singular_configuration_ahead) is named.
  std::string newton_failure_message(double t_n, double h, double residual, int iterations,
                                     int body) const;

  const core::Model& model_;
  detail::GenAlphaSystem system_;
  double time_ = 0.0;
  double last_h_ = 0.0;
  bool restart_pending_ = true;
  bool initialized_ = false;      ///< a_0 = v̇_0 set (restarts keep a_n)
  bool lambda_unscaled_ = false;  ///< lambda_hat_ holds λ_n from restart(), not β h² λ_n
  core::State state_;
  core::State next_;
  core::Workspace ws_;
  /// The joints' rows in force and the last accepted state's rows: advanced only on accepted
  /// steps (track_joints), read by the restarts' evaluations.
  core::ConstraintTracker tracker_;
  detail::WearDepthUpdate wear_;  ///< the worn depths' rates
  core::Accelerations acc_;
  Eigen::VectorXd vdot_;           ///< v̇_n
  Eigen::VectorXd a_;              ///< a_n
  Eigen::VectorXd vdot_next_;      ///< v̇_{n+1}
  Eigen::VectorXd a_next_;         ///< a_{n+1}
  Eigen::VectorXd lambda_hat_;     ///< β h² λ_n
  Eigen::VectorXd lambda_saved_;   ///< λ̂_n while a step's joints are checked
  Eigen::VectorXd z_;              ///< Newton unknowns
  Eigen::VectorXd r_;              ///< residual
  Eigen::VectorXd dz_;             ///< correction
  Eigen::VectorXd z_base_;         ///< the iterate a fresh correction was computed at
  Eigen::SparseMatrix<double> S_;  ///< iteration matrix, the pattern of pattern_rows_
  SparseLu lu_;                    ///< its sparse LU (ordered once per pattern)
  std::vector<int> pattern_rows_;  ///< the rows in force S_'s pattern and lu_'s ordering are for
  bool matrix_valid_ = false;      ///< lu_ holds a factored matrix of step length matrix_h_
  double matrix_h_ = 0.0;
  long evaluations_at_start_ = 0;
  long newton_iterations_ = 0;
  int max_newton_iterations_ = 0;
  long steps_ = 0;
};

}  // namespace flexref::lie
