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
/// independent ones are chosen at the model's consistent initial state by the maximal model's
/// rank-revealing choice (core::independent_rows on J_c); the others are redundant (a planar
/// loop's out-of-plane rows). In motion an integrator carries them in a ClosureTracker, which
/// the maximal tracker's rules move (core/constraint_tracker.hpp, docs/joints.md): rows chosen
/// again where their pivot ratio falls, and the orientation test for a singular configuration
/// passed between the last accepted state and the one solved now. An evaluation evaluates the
/// closure rows in force alone (Andrews: 6 of 15), all of them only where it chooses rows. The
/// solve is the Schur complement of the small system:
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
  core::Workspace model;           ///< the maximal model's scratch: loads and kinematics
  core::ConstraintRows rows;       ///< the closures' rows, J by its blocks
  core::Accelerations bias;        ///< Ṡ u body by body (dynamics_residual's argument)
  Eigen::VectorXd residual;        ///< 6N: M Ṡ u − Q
  Eigen::MatrixXd M_r;             ///< n_u × n_u (its lower triangle), then L − diag(L)
  Eigen::VectorXd M_r_inv_diag;    ///< n_u: 1/L(j,j), M_r = L Lᵀ
  Eigen::VectorXd Q_r;             ///< n_u
  Eigen::MatrixXd J_c;             ///< m × n_u
  Eigen::VectorXd gamma_c;         ///< m
  Eigen::VectorXd velocity_rows;   ///< m: J_c u + Φ_t
  Eigen::MatrixXd J_a;             ///< r × n_u, the independent rows
  Eigen::VectorXd rhs;             ///< r
  Eigen::VectorXd lambda;          ///< r: the independent rows' multipliers
  Eigen::MatrixXd W;               ///< r × n_u: J_a L⁻ᵀ
  Eigen::MatrixXd A;               ///< r × r: W Wᵀ = J_a M_r⁻¹ J_aᵀ, then L_A − diag(L_A)
  Eigen::VectorXd A_diag;          ///< r: L_A(j,j), A = L_A L_Aᵀ
  Eigen::VectorXd A_inv_diag;      ///< r: 1/L_A(j,j)
  Eigen::VectorXd correction;      ///< n_u: M_r⁻¹ J_aᵀ λ
  Eigen::Index schur_failed = -1;  ///< A's failed pivot (cholesky_in_place), or −1
  /// (min/max)² of the Schur factor's diagonal over the rows solved with: the ratio of A's
  /// pivots, as the maximal solve's (core/schur_complement_tpl.hpp).
  double pivot_ratio = 0.0;
  /// Rows this evaluation chose for itself (rows_chosen) where the tracker's had become
  /// ill-conditioned or turned through a dependency; ClosureTracker takes them at the next
  /// accepted state.
  std::vector<int> chosen;
  bool rows_chosen = false;
  /// A closure row turned by more than core::kOrientationTestCosine's angle since the tracker's
  /// accepted state, where the orientation test is not conclusive: an integrator must not accept
  /// a step from this evaluation, but take a shorter one.
  bool rows_turned = false;
  std::vector<int> solved;        ///< the rows the last evaluation solved with (λ's rows)
  Eigen::MatrixXd crossing;       ///< r × r: J_a,accepted M_r⁻¹ J_aᵀ (the orientation test)
  Eigen::MatrixXd accepted_rows;  ///< r × n_u: J_a,accepted L⁻ᵀ (the orientation test)
  /// r × 2: |x_i|², |w_i|² (the orientation test; |w_i|² = A(i,i), kept by factor_closures)
  Eigen::MatrixXd row_norms;
  /// m: 1 for the closure rows this evaluation evaluated (rows, J_c, γ_c, velocity_rows): the
  /// rows in force, or all of them where it chose rows of its own. The others are zero or stale.
  std::vector<char> evaluated;
  /// The evaluation's time and coordinates, which ClosureTracker keeps at an accepted state.
  double t = 0.0;
  Eigen::VectorXd q, u;
  /// The closures at the tracker's accepted state, all rows, evaluated again from its (t, q, u)
  /// where this evaluation chose rows that were not in force there (ReducedModel::orientation):
  /// the tree, the bodies' kinematics, the rows and J_c (γ_c: assembly's scratch).
  TreeWorkspace accepted_tree;
  std::vector<core::BodyKinematics> accepted_kinematics;
  core::ConstraintRows accepted_closures;
  Eigen::MatrixXd accepted_J_c;      ///< m × n_u
  Eigen::VectorXd accepted_gamma_c;  ///< m
  /// 6 × Σ_b c_b: M_b S_i on each body's c_b columns of S, body after body (M_r's products)
  Eigen::Matrix<double, 6, Eigen::Dynamic> MS;
};

/// The closures' history an integrator carries from one accepted state to the next (the reduced
/// form's core::ConstraintTracker): the independent closure rows in force, the pivot ratio they
/// were chosen at, and J_c at the last accepted state, against which every solve tests the rows'
/// orientation. Only ReducedModel::accept moves it, at a state the integrator accepted.
struct ClosureTracker {
  std::vector<int> rows;
  double selection_ratio = 0.0;  ///< 0: the first accepted solve's ratio is taken
  /// m × n_u, the rows the accepted evaluation evaluated (`evaluated`): the rows in force there,
  /// all of them where it chose rows; the others are evaluated again from (t, q, u) when rows
  /// chosen later need them.
  Eigen::MatrixXd J_accepted;
  std::vector<char> evaluated;  ///< m
  double evaluated_time = 0.0;  ///< the accepted evaluation's t, q and u
  Eigen::VectorXd q, u;
  double accepted_time = 0.0;
  bool has_accepted = false;
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
  /// The initial configuration's rows, nothing accepted yet.
  ClosureTracker make_tracker() const;
  /// Moves `tracker` to the state of the last evaluation in `ws`, which the integrator accepted
  /// at time t (or one within its tolerance of it: the last corrector iterate of the step it
  /// accepted): the rows that evaluation chose, if it chose any, and its J_c as the orientation
  /// test's reference. Allocates nothing.
  void accept(double t, const ReducedWorkspace& ws, ClosureTracker& tracker) const;

  /// The joint coordinates of the model's consistent initial state.
  const Vector& initial_positions() const { return q0_; }
  const Vector& initial_velocities() const { return u0_; }
  /// The joint coordinates of a maximal state (TreeKinematics::coordinates).
  void coordinates(const core::State& state, Vector& q, Vector& u) const {
    kinematics_.coordinates(state, q, u);
  }
  /// u̇ at (context, q, u) with Baumgarte's rate `stabilization` on the closures (1/s; 0: the
  /// index-1 form), on `tracker`'s rows (null: the initial configuration's, no orientation test).
  /// Where those rows are ill-conditioned (core::kReselectPivotRatio, or their ratio fell by
  /// core::kReselectPivotFall since they were chosen) or turned through a dependency among
  /// themselves, the evaluation chooses rows of its own (ws.rows_chosen; allocating, the rare
  /// path). Throws core::SingularConfigurationError where the closure rows lose rank, or where
  /// the orientation test finds a singular configuration passed since the tracker's accepted
  /// state; sets ws.rows_turned where the rows turned too far for the test. Allocates nothing
  /// otherwise. The loads and the closures take the bodies' attitude matrices from the forward
  /// kinematics (Model::compute_wrenches' second form): ws.tree.state's Euler parameters are
  /// left NaN for attitudes() (TreeKinematics::evaluate), which a caller that reads them calls.
  void accelerations(const core::LoadContext& context, const Vector& q, const Vector& u,
                     ReducedWorkspace& ws, Vector& u_dot, double stabilization = 0.0,
                     const ClosureTracker* tracker = nullptr) const;
  /// The bodies' Euler parameters θ_WB at the last evaluation's state (ws.tree.state), which
  /// accelerations leaves NaN: the forward kinematics' own conversion. Allocates nothing.
  void attitudes(ReducedWorkspace& ws) const { kinematics_.attitudes(ws.tree); }
  /// The closures' stacked generalized force on the bodies, −J_aᵀ λ (6 per body, the maximal
  /// model's velocity layout), at the last evaluation in `ws`: what Model::integral_rates reads
  /// for the drives' power (the tree joints are never driven and do no work).
  void closure_force(const ReducedWorkspace& ws, Vector& force) const;
  /// The bodies' accelerations S u̇ + Ṡ u at the last evaluation's state.
  void body_accelerations(const ReducedWorkspace& ws, const Vector& u_dot,
                          core::Accelerations& accelerations) const;

 private:
  const core::Model* model_;
  TreeKinematics kinematics_;
  ReducedModel(const core::Model& model, const core::State& initial);
  /// Factors A = J_a M_r⁻¹ J_aᵀ on `rows` (J_a, W, A, schur in ws) and returns its pivot ratio
  /// (0 where the factorization fails).
  double factor_closures(const std::vector<int>& rows, ReducedWorkspace& ws) const;
  /// The closure rows marked in ws.evaluated at the poses in ws (ws.model.kinematics, ws.tree)
  /// into ws.rows, J_c = J S and γ_c = γ − J Ṡ u, and with Baumgarte's rate a ≠ 0 their
  /// velocity rows J_c u + Φ_t; the others' entries of J_c zero.
  void evaluate_closures(double t, const Vector& u, double a, ReducedWorkspace& ws) const;
  /// The closures' rows at the tracker's accepted state, all of them, into ws.accepted_J_c: the
  /// accepted evaluation's own arithmetic from its (t, q, u), so the same bits as its J_c had for
  /// the rows it evaluated. The rare path (rows chosen that were not in force there).
  void evaluate_accepted_closures(const ClosureTracker& tracker, ReducedWorkspace& ws) const;
  /// Each body's kinematics at the poses of `tree` as Model::compute_wrenches poses them from the
  /// tree's attitude matrices, for the closures at the accepted state.
  void pose_bodies(const TreeWorkspace& tree, std::vector<core::BodyKinematics>& bodies) const;
  /// The independent rows of ws.J_c, the rows the tree satisfies identically set aside (each
  /// row against its own scale; reduced_model.cpp). Allocates.
  std::vector<int> independent_closure_rows(const ReducedWorkspace& ws) const;
  /// The independent rows of J_c at this evaluation (at t, u, Baumgarte's rate a; every closure
  /// row evaluated first) into ws.chosen (ws.rows_chosen), factored; false where fewer than the
  /// rows in force remain independent (rank lost). Allocates.
  bool choose_closure_rows(double t, const Vector& u, double a, ReducedWorkspace& ws) const;
  /// The sign of det(J_a,accepted M_r⁻¹ J_aᵀ) on `rows`, factored in ws
  /// (core/orientation_test_tpl.hpp's test in joint space): +1 kept, −1 turned through a
  /// dependency; 0 where a row turned by more than kOrientationTestCosine's angle (in M_r⁻¹'s
  /// metric), where the test is not conclusive.
  int orientation(const std::vector<int>& rows, const ClosureTracker& tracker,
                  ReducedWorkspace& ws) const;
  /// The closure joint of the smallest pivot of A on `rows` (the row nearest to dependence).
  int smallest_pivot_joint(const std::vector<int>& rows, const ReducedWorkspace& ws) const;
  [[noreturn]] void throw_singular(const std::vector<int>& rows, const ReducedWorkspace& ws,
                                   double t) const;
  [[noreturn]] void throw_passed_singular(const std::vector<int>& rows, const ReducedWorkspace& ws,
                                          double t0, double t1) const;

  std::unique_ptr<IdealJoints> closures_;
  std::vector<int> active_;
  Vector q0_, u0_;
};

}  // namespace flexref::constraint
