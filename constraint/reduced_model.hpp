#pragma once
/// \file reduced_model.hpp
/// The equations of motion of a jointed model of rigid bodies in joint coordinates
/// (docs/reduced_coordinates.md): the spanning tree's coordinates (q, u) carry the tree joints
/// exactly, the loop closures keep their rows of constraint/ideal_joints.hpp with multipliers.
/// With v = S u, v̇ = S u̇ + Ṡ u (constraint/tree_kinematics.hpp), the maximal equations
/// M v̇ + Jᵀ λ = Q, J v̇ = γ (core/constraint_equations.hpp) become, premultiplied by Sᵀ (the tree
/// joints' reactions do no virtual work along S: J_tree S = 0),
///   M_r u̇ + J_cᵀ λ_c = Q_r,   J_c u̇ = γ_c,
///   M_r = Sᵀ M S,  Q_r = Sᵀ (Q − M Ṡ u),  J_c = J S,  γ_c = γ − J Ṡ u,
/// J, γ the closures' rows evaluated at the bodies' forward-kinematics poses, Q the bodies'
/// applied and velocity-product forces as core::Model computes them (its dynamics_residual at
/// the accelerations Ṡ u is M Ṡ u − Q, so Q_r = −Sᵀ r(Ṡ u)). Of the closure rows, the
/// independent ones are chosen once, at the model's consistent initial state, by the maximal
/// model's rank-revealing choice (core::independent_rows on J_c); the others are redundant
/// (a planar loop's out-of-plane rows). The solve is the Schur complement of the small system:
///   u̇₀ = M_r⁻¹ Q_r,   (J_a M_r⁻¹ J_aᵀ) λ = J_a u̇₀ − γ_a,   u̇ = u̇₀ − M_r⁻¹ J_aᵀ λ,
/// both matrices by Cholesky (constraint/small_cholesky.hpp): with M_r = L Lᵀ and W = J_a L⁻ᵀ,
/// J_a M_r⁻¹ J_aᵀ = W Wᵀ and M_r⁻¹ J_aᵀ λ = L⁻ᵀ (Wᵀ λ). Baumgarte's term, as the maximal form's,
/// replaces γ_a by γ_a − 2α (J_a S u + Φ_t) − α² Φ_a.
///
/// Refused (std::invalid_argument naming the reason): flexible and prescribed bodies
/// (constraint/spanning_tree.hpp), constraints other than ideal joints, and force elements with
/// switching functions or worn depths (contact: their events need the maximal references'
/// event location, which the reduced form does not have).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "constraint/ideal_joints.hpp"
#include "constraint/tree_kinematics.hpp"
#include "core/model.hpp"

namespace flexref::constraint {

/// Per-evaluation scratch of ReducedModel (sized once; evaluations allocate nothing).
struct ReducedWorkspace {
  TreeWorkspace tree;
  core::Workspace model;          ///< the maximal model's scratch: loads and kinematics
  core::ConstraintRows rows;      ///< the closures' rows, J by its blocks
  core::Accelerations bias;       ///< Ṡ u body by body (dynamics_residual's argument)
  Eigen::VectorXd residual;       ///< 6N: M Ṡ u − Q
  Eigen::MatrixXd M_r;            ///< n_u × n_u (its lower triangle), then L − diag(L)
  Eigen::VectorXd M_r_inv_diag;   ///< n_u: 1/L(j,j), M_r = L Lᵀ
  Eigen::VectorXd Q_r;            ///< n_u
  Eigen::MatrixXd J_c;            ///< m × n_u
  Eigen::VectorXd gamma_c;        ///< m
  Eigen::VectorXd velocity_rows;  ///< m: J_c u + Φ_t
  Eigen::MatrixXd J_a;            ///< r × n_u, the independent rows
  Eigen::VectorXd rhs;            ///< r
  Eigen::VectorXd lambda;         ///< r: the independent rows' multipliers
  Eigen::MatrixXd W;              ///< r × n_u: J_a L⁻ᵀ
  Eigen::MatrixXd A;              ///< r × r: W Wᵀ = J_a M_r⁻¹ J_aᵀ, then L_A − diag(L_A)
  Eigen::VectorXd A_diag;         ///< r: L_A(j,j), A = L_A L_Aᵀ
  Eigen::VectorXd A_inv_diag;     ///< r: 1/L_A(j,j)
  Eigen::VectorXd correction;     ///< n_u: M_r⁻¹ J_aᵀ λ
};

class ReducedModel {
 public:
  using Vector = Eigen::VectorXd;

  /// The reduced form of `model`, which must outlive it. Throws std::invalid_argument for what
  /// it refuses (see the file comment).
  explicit ReducedModel(const core::Model& model);

  const core::Model& model() const { return *model_; }
  const TreeKinematics& kinematics() const { return kinematics_; }
  int position_count() const { return kinematics_.position_count(); }
  int velocity_count() const { return kinematics_.velocity_count(); }
  /// The closure rows (rows of closure_joints()) the solve enforces.
  const std::vector<int>& independent_rows() const { return active_; }
  /// The loop-closure joints alone (their rows in the order of the tree's closures), or null.
  const IdealJoints* closure_joints() const { return closures_.get(); }
  ReducedWorkspace make_workspace() const;

  /// The joint coordinates of a maximal state (TreeKinematics::coordinates).
  void coordinates(const core::State& state, Vector& q, Vector& u) const {
    kinematics_.coordinates(state, q, u);
  }
  /// u̇ at (context, q, u) with Baumgarte's rate `stabilization` on the closures (1/s; 0: the
  /// index-1 form). Throws core::SingularConfigurationError where the enforced closure rows lose
  /// rank. Allocates nothing.
  void accelerations(const core::LoadContext& context, const Vector& q, const Vector& u,
                     ReducedWorkspace& ws, Vector& u_dot, double stabilization = 0.0) const;
  /// The bodies' accelerations S u̇ + Ṡ u at the last evaluation's state.
  void body_accelerations(const ReducedWorkspace& ws, const Vector& u_dot,
                          core::Accelerations& accelerations) const;

 private:
  const core::Model* model_;
  TreeKinematics kinematics_;
  std::unique_ptr<IdealJoints> closures_;
  std::vector<int> active_;
};

}  // namespace flexref::constraint
