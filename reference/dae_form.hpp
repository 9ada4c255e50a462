#pragma once
/// \file dae_form.hpp
/// The DAE form F(t, y, y') = 0 that IDA integrates (docs/references.md, "IDA"): the
/// quasi-velocity equations of docs/design/model.md in residual form, with the mass matrix
/// multiplying the accelerations instead of being factorized. Per body
///   free  y = [p(3) θ(4) v(3) ω̄(3) q(n) v_q(n)],  pivot y = [θ(4) ω̄(3) q(n) v_q(n)],
///   prescribed y = [q(n) v_q(n)]   (q, v_q only for a flexible body)
///   ṗ − v = 0
///   θ̇ − ½ θ ⊗ (0, ω̄) = 0
///   q̇ − v_q = 0
///   M(θ̂, q) (v̇, ω̄̇, v̇_q) − (Qe + Qv − [0; 0; K q + D v_q]) = 0
///                        (Model::dynamics_residual: translation, rotation in the body frame,
///                         modal rows; θ̂ = θ/|θ| in every load and in A)
/// then the contacts' worn depths, ḣ − Model::wear_depth_rates = 0 (docs/wear.md), and, last,
/// when the model dissipates, Ẇ_d − P = 0 (the dissipated work). The layout of y is
/// the ODE form's (reference/ode_form.hpp): a Jacobian of the ODE right-hand side serves IDA
/// too (reference/ode_jacobian.hpp).
///
/// With ideal joints (docs/joints.md) the form is the stabilized index-2 system of Gear, Gupta &
/// Leimkuhler (1985) in the quasi-velocity variables, the multipliers λ, μ of the m independent
/// rows last in y (algebraic: IDASetId 0, out of the error test):
///   ṗ − v + Φ_pᵀ μ = 0,   θ̇ − ½ θ ⊗ (0, ω̄) + 2 Ḡ(θ̂)ᵀ J_ω̄ᵀ μ = 0,   q̇ − v_q + J_q̇ᵀ μ = 0,
///   M v̇ − Q + Jᵀ λ = 0,   J v + Φ_t = 0,   Φ(q, t) = 0,
/// (Φ_p = J_v, ∂Φ/∂θ = J_ω̄ 2Ḡ(θ̂) since δφ_B = 2 Ḡ δθ); on the exact solution μ = 0 and λ are the
/// joints' multipliers. Without joints ∂F/∂y' = blockdiag(I, M) is regular: an implicit ODE
/// (index 0), every component differential. |θ| is a first integral of the kinematic equation (θᵀ
/// (θ ⊗ (0, ω̄)) = 0), and the equations are homogeneous in θ, so a drift of |θ| by the local errors
/// does not move the attitude θ̂; the driver renormalizes θ at every restart. *Decision* (measured
/// against the paper's Euler-parameter form and a GGL-constrained variant, docs/references.md): no
/// constraint and no multiplier. BDF damps and dephases the oscillation the Euler-parameter
/// velocities v_θ = θ̇ carry even in a steady spin, where ω̄ is constant; and a GGL multiplier
/// on |θ| = 1 puts the predictor's normal displacement into IDA's local error estimate (CVODE's
/// projection removes it, IDA has no such hook), which costs 2–3× the steps.
#include <cstddef>
#include <span>
#include <vector>

#include "core/model.hpp"
#include "reference/form_layout.hpp"

namespace flexref::reference {

class DaeForm {
 public:
  explicit DaeForm(const core::Model& model);

  struct Scratch {
    core::State state;
    core::Workspace workspace;
    core::Accelerations accelerations;
    Eigen::VectorXd residual;
    std::vector<int> generalized_rows;       ///< mass_rows: a body's rows in y
    std::vector<Eigen::MatrixXd> body_mass;  ///< mass_rows: a flexible body's (6+n)² matrix
    Eigen::VectorXd velocities;              ///< ideal joints: the stacked (v_Br, ω̄, q̇_f)
    core::ConstraintRows rows;               ///< ideal joints: all rows at the iterate
    Eigen::VectorXd multipliers;             ///< ideal joints: Jᵀ λ, then Jᵀ μ (stacked)
    Eigen::VectorXd constraint_force;        ///< ideal joints: −Jᵀ λ, for the drives' power
  };

  int size() const { return size_; }
  const core::Model& model() const { return *model_; }
  Scratch make_scratch() const;

  /// Consistent initial values y, y' from a state (y' from the quasi-velocity form's
  /// accelerations). θ is taken as given (the drivers pass unit Euler parameters).
  void initial_values(const core::LoadContext& context, const core::State& state, double* y,
                      double* yp) const;
  void residual(const core::LoadContext& context, const double* y, const double* yp, double* res,
                Scratch& scratch) const;
  /// P = ∂F/∂y' at (context, y) into `mass` (size() square): the identity in the kinematic rows
  /// (p, θ, q, W_d) and each body's mass matrix M(θ̂, q) in its dynamics rows (v, ω̄, v_q),
  /// restricted to the rows and columns the body integrates. F is linear in y', so P is exact.
  void mass_rows(const core::LoadContext& context, const double* y,
                 Eigen::Ref<Eigen::MatrixXd> mass, Scratch& scratch) const;
  /// State at time t and y (θ normalized; prescribed bodies follow their law; the worn depths).
  void unpack(double t, const double* y, core::State& state) const;
  /// Index of the first worn depth in y and their count (Model::wear_depth_count()).
  int depth_index() const { return depth_index_; }
  int depth_count() const { return depth_count_; }

  /// Index of the dissipated work W_d in y (differential, W_d' = dissipated power), or −1.
  int work_index() const { return work_index_; }
  double dissipated_work(const double* y) const { return work_index_ < 0 ? 0.0 : y[work_index_]; }
  /// Sets W_d in y (the initial values set it to 0).
  void set_dissipated_work(double* y, double work) const {
    if (work_index_ >= 0) y[work_index_] = work;
  }
  /// The integrals tracked with the state (Model::integral_rates): W_d then the model's extra
  /// integrals (applied work, wear work per contact), from work_index(); 0 when not tracked.
  int integral_count() const { return integral_count_; }
  /// Copies them out of y (integral_count() values) / into y.
  void integrals(const double* y, std::span<double> out) const {
    for (int j = 0; j < integral_count_; ++j) out[static_cast<std::size_t>(j)] = y[work_index_ + j];
  }
  void set_integrals(double* y, std::span<const double> values) const {
    for (int j = 0; j < integral_count_; ++j)
      y[work_index_ + j] = values[static_cast<std::size_t>(j)];
  }

  /// Ideal joints: the first multiplier in y (λ of the independent rows, then μ), their count m
  /// (each), −1 and 0 without joints.
  int multiplier_index() const { return multiplier_index_; }
  int multiplier_count() const { return multiplier_count_; }
  /// The joint rows λ and μ belong to: the model's independent rows at the start, chosen again
  /// in motion (the IDA driver's row switch, at a restart: initial_values maps λ to them).
  const std::vector<int>& active_rows() const { return active_; }
  void set_active_rows(const std::vector<int>& rows) { active_ = rows; }
  /// 1 for a component of y in IDA's error test, 0 for one out of it (IDASetId with
  /// IDASetSuppressAlg): with ideal joints the multipliers (algebraic) and the works.
  std::vector<double> differential_ids() const;

  /// Offsets of a body's blocks in y (reference/form_layout.hpp, the ODE form's too; qd is
  /// v_q's).
  using Block = BodyBlock;
  const std::vector<Block>& blocks() const { return blocks_; }

 private:
  const core::Model* model_;
  core::State fixed_;
  std::vector<Block> blocks_;
  int size_ = 0;
  int max_rows_ = 6;
  int depth_index_ = 0;
  int depth_count_ = 0;
  int work_index_ = -1;
  int integral_count_ = 0;
  int multiplier_index_ = -1;
  int multiplier_count_ = 0;
  std::vector<int> active_;
};

}  // namespace flexref::reference
