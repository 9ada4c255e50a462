#pragma once
/// \file genalpha_newton.hpp
/// The nonlinear equations of one Lie-group generalized-α step (Brüls, Cardona & Arnold 2012,
/// docs/schemes.md "Lie-group generalized-α") and their iteration matrix, exposed so that tests
/// can check the matrix against finite differences of the residual.
///
/// Unknowns z = (x, λ̂): per body the increment x = h Δq_n (translation of Br, world; the
/// rotation vector, body frame; for a flexible body its n modal coordinates, a vector space) with
/// q_{n+1} = q_n ∘ exp(x) on SO(3) × R³ × Rⁿ, and the scaled multipliers λ̂ = β h² λ of the
/// independent joint rows. Body b occupies 6 + n_b entries of x, in the order of the joints'
/// velocity layout (v_WBr, ω̄, q̇_f). From x (a_n, v̇_n, v_n of step n):
///   a_{n+1} = (x/h − v_n − (½ − β) h a_n)/(β h)
///   v̇_{n+1} = ((1 − α_m) a_{n+1} + α_m a_n − α_f v̇_n)/(1 − α_f)
///   v_{n+1} = v_n + (1 − γ) h a_n + γ h a_{n+1}
/// Residual (the model's equations of motion at t_{n+1}, Model::dynamics_residual, times β h²,
/// then the position constraints):
///   r_b = β h² ( M_b v̇_b − Q_b(q, v, t) + (Jᵀ λ)_b ),    r_Φ = Φ(q_{n+1}, t_{n+1})
/// (a rigid body: [m v̇_T − f_W ;  J v̇_R + W × J W − Rᵀ τ_W]; a flexible body: the coupled or LTE
/// rows of core/model.hpp). Iteration matrix ∂r/∂z (index 3 with the scaling of the dynamic rows
/// by β h² and of λ by 1/(β h²), which makes every block O(1) as h → 0 instead of the unscaled
/// O(h⁻²) spread):
///   S = [ β h² (M β' + C γ' + K T) + ∂(Jᵀ λ̂)/∂x ,  Jᵀ ]      β' = (1 − α_m)/((1 − α_f) β h²)
///       [ J T                                 ,  0  ]      γ' = γ/(β h)
/// with T = blockdiag(I, T_SO3(x_R), I) the tangent operator of the exponential map (the right
/// Jacobian: q exp(x + δ) = q exp(x) exp((T δ)~) + O(δ²)). Analytic: the mass matrix M (a
/// flexible body's from Model::residual_mass_matrix), and for a rigid body the gyroscopic
/// damping W̃ J − (J W)~ and the rotation of the world torque into the body frame, −(Rᵀτ)~ T.
/// Finite differences: the force elements' stiffness and damping, K T + C γ', by one forward
/// difference of the model's wrenches per colour of bodies and unknown (the unknown moved in
/// every body of the colour at once; two bodies share a colour only when no body's equations
/// read both, core/body_coupling.hpp, so each difference is one body's column, the quotient the
/// body-by-body difference forms: 6 × 3 evaluations on a chain, whatever its length) along the
/// direction that unknown moves the state (configuration by ε T e_k, velocity by ε γ' e_k), ε
/// = 1.5e-8 (√ε_mach: truncation ε |f''| and round-off ε_mach |f|/ε balance at ~1e-8 relative); for
/// a flexible body the same difference of its whole residual at fixed v̇ (loads, elastic and damping
/// forces, and the velocity- and configuration-dependent inertia terms); the joints' geometric
/// stiffness ∂(Jᵀ λ̂)/∂x from the rows at the same perturbed configurations.
///
/// Rows a body does not integrate (a pivot's translation, the rigid six of a prescribed body)
/// have r = m̂ x and the matrix m̂ I (m̂: the scaled mass or inertia diagonal), so they stay at
/// x = 0; a prescribed body's rigid motion follows its law.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "core/model.hpp"
#include "lie/genalpha_parameters.hpp"

namespace flexref::lie::detail {

/// How far a residual is from zero, relative to the size of the terms it is the sum of.
struct GenAlphaResidualNorm {
  bool finite = true;
  double relative = 0.0;  ///< largest relative component (dynamics and constraints)
  int worst_body = 0;     ///< body (or, for a constraint row, its first body) where it is
};

class GenAlphaSystem {
 public:
  /// The model must outlive the system.
  GenAlphaSystem(const core::Model& model, const GenAlphaParameters& parameters);

  int size() const { return static_cast<int>(z_size_); }
  /// Σ_b (6 + n_b): the stacked velocities (the model's velocity_layout()); body b from
  /// offset(b).
  int body_unknowns() const { return layout_.size(); }
  int offset(int body) const { return layout_.offset(body); }
  int multiplier_count() const { return n_multipliers_; }
  /// The joint rows the multipliers λ̂ belong to (the model's independent rows at the start;
  /// chosen again in motion by the stepper, same count: set_active_rows).
  const std::vector<int>& active_rows() const { return active_; }
  void set_active_rows(const std::vector<int>& rows) { active_ = rows; }
  const GenAlphaParameters& parameters() const { return p_; }

  /// Starts a step from t_n with the state, v̇_n and a_n (stacked). Must be called
  /// before predictor, residual and iteration_matrix.
  /// The worn depths the step's loads see (the stepper's predicted h̃_{n+1},
  /// lie/wear_depth_update.hpp): the residual's and the Jacobian's states take them.
  void set_wear_depth(const Eigen::VectorXd& depth) {
    next_.wear_depth = depth;
    perturbed_.wear_depth = depth;
  }
  void begin_step(double t_n, double h, const core::State& state, const Eigen::VectorXd& vdot_n,
                  const Eigen::VectorXd& a_n);
  /// The predictor z⁰: v̇_{n+1} = 0 (Brüls, Cardona & Arnold's) and λ̂ the last step's.
  void predictor(const Eigen::VectorXd& lambda_hat, Eigen::VectorXd& z) const;
  /// The state, v̇_{n+1} and a_{n+1} of the unknowns z (no evaluation). Prescribed bodies follow
  /// their law at t_{n+1}.
  void state_at(const Eigen::VectorXd& z, core::State& next, Eigen::VectorXd& vdot,
                Eigen::VectorXd& a) const;
  /// r(z): one evaluation of the model's loads at t_{n+1}. Leaves the loads, rows and state of z
  /// in the system for iteration_matrix.
  GenAlphaResidualNorm residual(const Eigen::VectorXd& z, Eigen::VectorXd& r);
  /// S's pattern at the rows in force, its values zero (compressed): the blocks of coupled
  /// bodies (core/body_coupling.hpp), each multiplier's column and row on its row's bodies, the
  /// diagonal. Allocates: once per set of rows in force.
  void make_iteration_matrix(Eigen::SparseMatrix<double>& S) const;
  /// S = ∂r/∂z at the z of the last residual call into the values of a matrix with
  /// make_iteration_matrix's pattern (matrix_evaluations() evaluations). Allocates nothing.
  void iteration_matrix(const Eigen::VectorXd& z, Eigen::SparseMatrix<double>& S);
  /// The same, dense (for tests; allocates).
  void iteration_matrix(const Eigen::VectorXd& z, Eigen::MatrixXd& S);
  /// Force evaluations made since construction.
  long evaluations() const { return evaluations_; }
  /// Evaluations one iteration_matrix call costs.
  int matrix_evaluations() const { return matrix_evaluations_; }
  /// Stacked velocities (v_WBr, ω̄, q̇_f) of a state, and accelerations into a stacked vector.
  void stack_velocities(const core::State& state, Eigen::VectorXd& v) const {
    layout_.stack_velocities(state, v);
  }
  void stack_accelerations(const core::Accelerations& acc, Eigen::VectorXd& x) const {
    layout_.stack_accelerations(acc, x);
  }

 private:
  bool integrated_row(int body, int k) const { return layout_.integrated(body, k); }
  /// Whether unknown k of body j is one the differences move (an integrated row of the body).
  bool moves(int j, Eigen::Index k) const {
    return k < offset(j + 1) - offset(j) && integrated_row(j, static_cast<int>(k));
  }
  /// out += Σ_a J_aᵀ λ̂_a over the rows in force, each row on its bodies' blocks only (terms:
  /// the same with absolute values, when given).
  void add_rows_transpose(const core::ConstraintRows& rows, const Eigen::VectorXd& z,
                          Eigen::VectorXd& out, Eigen::VectorXd* terms) const;
  /// Model::dynamics_residual of body b with v̇ = vdot_ (prescribed: the law's α̅), into
  /// body_residual_[b], at the loads and kinematics compute_wrenches left in ws_.
  void body_residual(int b, const core::Loads& loads);

  const core::Model& model_;
  GenAlphaParameters p_;
  int n_bodies_ = 0;
  int n_multipliers_ = 0;
  Eigen::Index z_size_ = 0;
  int matrix_evaluations_ = 0;
  std::vector<std::vector<int>> coupling_;  ///< per body, the bodies its equations read
  std::vector<std::vector<int>> colours_;   ///< the bodies of each colour (colour_bodies)
  std::vector<int> source_;  ///< per body, the body of the colour being differenced it reads
  const core::VelocityLayout& layout_;  ///< the model's stacked coordinates
  std::vector<int> active_;             ///< the rows of the multipliers (active_rows)
  double t_n_ = 0.0;
  double h_ = 0.0;
  const core::State* state_n_ = nullptr;
  Eigen::VectorXd v_n_;       ///< stacked (v_WBr, ω̄) at t_n
  Eigen::VectorXd a_n_;       ///< a_n (stacked)
  Eigen::VectorXd vdot_n_;    ///< v̇_n (stacked)
  Eigen::VectorXd a_base_;    ///< a_{n+1} − x/(β h²)
  Eigen::VectorXd vdot_;      ///< v̇_{n+1} of the last residual
  Eigen::VectorXd a_;         ///< a_{n+1} of the last residual
  Eigen::VectorXd v_;         ///< v_{n+1} of the last residual
  Eigen::VectorXd diagonal_;  ///< m̂ per row: β h² M_kk β' = M_kk (1 − α_m)/(1 − α_f)
  core::State next_;          ///< the state of the last residual
  core::State perturbed_;     ///< a directional perturbation of next_
  core::Workspace ws_;
  std::vector<core::Wrench> wrenches_;               ///< the loads at next_
  std::vector<Eigen::Matrix3d> R_;                   ///< R_{n+1} per body
  core::Accelerations acc_;                          ///< v̇_{n+1} per body, for dynamics_residual
  std::vector<Eigen::VectorXd> body_residual_;       ///< per body, at next_ (flexible bodies)
  std::vector<Eigen::VectorXd> body_residual_base_;  ///< and at the base of iteration_matrix
  std::vector<Eigen::MatrixXd> mass_;                ///< per flexible body: residual_mass_matrix
  core::ConstraintRows rows_;                        ///< the joints' rows at next_
  core::ConstraintRows rows_perturbed_;              ///< and at a perturbed configuration
  Eigen::VectorXd jt_lambda_;                        ///< J_aᵀ λ̂ at next_ (6N)
  /// Σ_a |J_a| |λ̂_a| at next_: the sizes of the rows' reactions before they cancel in J_aᵀ λ̂
  /// (a prismatic guide's torques about a point off its line do), the residual's scale.
  Eigen::VectorXd jt_lambda_terms_;
  Eigen::VectorXd jt_lambda_perturbed_;  ///< and at a perturbed configuration
  long evaluations_ = 0;
};

}  // namespace flexref::lie::detail
