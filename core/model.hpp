#pragma once
/// \file model.hpp
/// The immutable model every integrator sees (Pinocchio's Model/Data split), in any scalar type S
/// (ModelTpl<S>; Model is the double one): bodies and
/// force elements, and the one narrow interface integrators use — loads, accelerations,
/// energy and momentum at a state. Scratch space lives in a separate Workspace, so no
/// evaluation allocates.
///
/// Equations (docs/design/model.md, quasi-velocity form, rigid bodies about Br):
///   free:  m a_WBr = f_W,                  I_Br α̅ + ω̄ × I_Br ω̄ = Aᵀ τ_Br_W
///   pivot: a_WBr = 0,                      I_Pv α̅ + ω̄ × I_Pv ω̄ = Aᵀ τ_Pv_W
/// and for a flexible body, about Br with v = (a_WBr, α̅, q̈_f):
///   coupled: M(θ, q_f) v = Qe + Qv − [0; 0; K q_f + D q̇_f]     (flexible/flexible_dynamics.hpp)
///   LTE:     the same blocks at q_f = 0, q̇_f = 0 and without the rigid rows' elastic terms
///            (M_Rf = M_θf = 0): rigid motion of the undeformed body first, then
///            m_ff q̈_f + D q̇_f + K q_f = Qe_f − Sᵀ Aᵀ a − Ī_θf0ᵀ α̅ − Σ m_k Φ_kᵀ ω̄̃ω̄̃ x_k,
///            with loads evaluated on the undeformed body (docs/design/model.md, "The LTE model").
/// Rows of known accelerations (pivot: a = 0; prescribed: a = 0 and the law's α̅) are moved to
/// the right-hand side. A flexible body's remaining rows are solved in O(n²) through the
/// constant factor of m_ff (flexible/mass_matrix_solve.hpp): coupled, by the Schur complement
/// of the unknown rigid rows; LTE, by block forward substitution. Its inertia terms cost
/// O(n²) (flexible/inertia_terms.hpp), independent of the number of nodes.
#include <array>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/body.hpp"
#include "core/constrained_solve_tpl.hpp"
#include "core/constraint_equations.hpp"
#include "core/constraint_projection_tpl.hpp"
#include "core/constraint_tracker.hpp"
#include "core/flexible_formulation.hpp"
#include "core/force_element.hpp"
#include "core/joint_multipliers_tpl.hpp"
#include "core/state.hpp"
#include "flexible/inertia_terms.hpp"
#include "flexible/mass_matrix_solve.hpp"

namespace flexref::core {

/// Scratch of one flexible body's evaluation (sized once; never reallocated).
template <typename S>
struct FlexibleScratchTpl {
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  flexible::InertiaTermsTpl<S> terms;      ///< M_rr, M_rf and Qv at the evaluated state
  flexible::MassSolveScratchTpl<S> solve;  ///< the structured solve's scratch
  Vector rhs;                              ///< Qe + Qv − [0; 0; K q + D q̇]
  Vector x;                                ///< (a, α̅, q̈_f)
  Vector residual;                         ///< dynamics_residual's rows (6+n), for outputs
  Vector zero;                             ///< n zeros (LTE: q_f and q̇_f the inertia terms see)
};
using FlexibleScratch = FlexibleScratchTpl<double>;

/// Per-evaluation scratch space (Pinocchio's Data); make one per thread with
/// Model::make_workspace(). Any evaluation may overwrite all of it: nothing in it is a setting
/// or history an evaluation reads from an earlier one (the time, the load branch and Baumgarte's
/// rate are arguments; the joints' rows in force and their history are the integrator's
/// ConstraintTracker).
template <typename S>
struct WorkspaceTpl {
  std::vector<BodyKinematicsTpl<S>> kinematics;
  std::vector<WrenchTpl<S>> wrenches;
  std::vector<FlexibleScratchTpl<S>> flexible;  ///< one per body (empty matrices for rigid bodies)
  std::vector<WearSampleTpl<S>> wear;           ///< one per wear channel (Model::wear_samples)
  /// The accelerations integral_rates solves for when it needs the drives' power on its own.
  std::vector<BodyAccelerationTpl<S>> integral_accelerations;
  /// The worn depths of the state last posed (StateTpl::wear_depth), which the model hands each
  /// element as its slice of them (LoadContextTpl::wear_depth).
  std::span<const S> wear_depth;
  ConstraintSolveTpl<S> constraint;  ///< the ideal joints' solve (empty without joints)
  /// A memo of the prescribed bodies' α̅ at prescribed_time (Model::apply_prescribed_motion with
  /// ws), which an evaluation at that very time reads instead of evaluating the laws again (in
  /// quad their trigonometry is a large part of an evaluation); the same values either way.
  std::vector<Eigen::Matrix<S, 3, 1>> prescribed_alpha;
  S prescribed_time = std::numeric_limits<S>::quiet_NaN();
};
using Workspace = WorkspaceTpl<double>;

template <typename S>
class ModelTpl;

/// The loads compute_wrenches left in a workspace: the time and load branch and the state they
/// were evaluated at. The functions that read a workspace's loads take it, so the order "loads
/// first" is in their signatures and the time they need comes with it; only the model makes one.
template <typename S>
class LoadsTpl {
 public:
  const LoadContextTpl<S>& context() const { return context_; }
  const StateTpl<S>& state() const { return *state_; }

 private:
  friend class ModelTpl<S>;
  LoadsTpl(const LoadContextTpl<S>& context, const StateTpl<S>& state)
      : context_(context), state_(&state) {}
  LoadContextTpl<S> context_;
  const StateTpl<S>* state_;
};
using Loads = LoadsTpl<double>;

/// Where each tracked integral sits in [W_d, extra integrals] (Model::integral_rates): W_d at 0,
/// then the applied work W_a, the drives' work W_drive, each wear channel's work. −1: absent;
/// count 0: the model tracks no work.
struct IntegralLayout {
  int count = 0;
  int applied = -1;
  int drive = -1;
  int first_wear = -1;
};

/// How a model with ideal joints treats a scene's initial state that violates its constraints
/// (docs/joints.md, "Initial state").
struct ConstraintOptions {
  /// Largest violation accepted and projected away silently, relative (length rows to the
  /// joints' largest arm, rotation rows as they are, velocity rows to the bodies' speeds).
  double initial_tolerance = 1e-6;
  /// Project whatever the violation (the scene's `project_initial_state = true`).
  bool project_initial_state = false;
  /// The independent constraint rows to keep (empty: chosen at the initial configuration). A
  /// model converted to another scalar type keeps the double model's, so both solve the same rows.
  std::vector<int> independent_rows;
};

/// A scene's initial state that violates its ideal joints by more than the tolerance: names
/// the joint, the level (position or velocity) and the relative violation.
class InconsistentInitialStateError : public std::invalid_argument {
 public:
  InconsistentInitialStateError(int joint, const std::string& what)
      : std::invalid_argument(what), joint_(joint) {}
  int joint() const { return joint_; }

 private:
  int joint_;
};

/// Joint data that double precision cannot resolve (docs/joints.md, "What a jointed solution
/// promises"): a joint point so far from its body that the body's rotation and translation no
/// longer both enter its rows, or rows that evaluate to inf or NaN. Names the joint and the end
/// (0: body_a's point, 1: body_b's).
class JointDataError : public std::invalid_argument {
 public:
  JointDataError(int joint, int end, const std::string& what)
      : std::invalid_argument(what), joint_(joint), end_(end) {}
  int joint() const { return joint_; }
  int end() const { return end_; }

 private:
  int joint_;
  int end_;
};

/// The largest relative violations of the joints' rows at a state (length rows by the joints'
/// length scale ℓ, rotation rows as they are; velocity rows by the bodies' speeds), their sizes
/// and the rows where they are.
template <typename S>
struct RelativeJointViolationTpl {
  S position = S(0);
  S velocity = S(0);
  S position_absolute = S(0);  ///< |Φ| of that row (m, or the sine of an angle)
  S velocity_absolute = S(0);  ///< |J v + Φ_t| of that row (m/s or rad/s)
  int position_row = 0;
  int velocity_row = 0;
  S speed = S(0);  ///< the velocity scale the velocity rows are relative to (m/s)
};
using RelativeJointViolation = RelativeJointViolationTpl<double>;

/// What the consistent initial state moved from the scene's: the largest relative position and
/// velocity violations before projection (0 without joints).
struct InitialProjection {
  double position = 0.0;
  double velocity = 0.0;
};

/// The scene's initial state made consistent with the ideal joints, and how far it moved.
template <typename S>
struct ConsistentInitialStateTpl {
  StateTpl<S> state;
  InitialProjection projection;
};

/// The model in scalar type S (Pinocchio's ModelTpl): double for every integrator, long double
/// and float128 for the precision references (precision/model_conversion.hpp converts a double
/// model). One class, so the equations, the state's layout and the joints are written once.
template <typename S>
class ModelTpl {
 public:
  using Scalar = S;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Body = BodyTpl<S>;
  using BodyState = BodyStateTpl<S>;
  using State = StateTpl<S>;
  using BodyAcceleration = BodyAccelerationTpl<S>;
  using Accelerations = AccelerationsTpl<S>;
  using Workspace = WorkspaceTpl<S>;
  using LoadContext = LoadContextTpl<S>;
  using ForceElement = ForceElementTpl<S>;
  using ConstraintEquations = ConstraintEquationsTpl<S>;
  using JointReaction = JointReactionTpl<S>;
  using FlexibleScratch = FlexibleScratchTpl<S>;
  using Loads = LoadsTpl<S>;
  using ConstraintTracker = ConstraintTrackerTpl<S>;
  using JointMultipliers = JointMultipliersTpl<S>;
  using ConsistentInitialState = ConsistentInitialStateTpl<S>;
  /// With ideal joints (`constraints`), the independent rows are chosen at the scene's initial
  /// configuration and the initial state is checked to be one that can be made consistent
  /// (initial_state): a violation beyond options.initial_tolerance throws
  /// InconsistentInitialStateError unless options.project_initial_state; a singular initial
  /// configuration throws SingularConfigurationError.
  ModelTpl(std::vector<Body> bodies, std::vector<std::unique_ptr<const ForceElement>> elements,
           FlexibleFormulation formulation = FlexibleFormulation::kCoupled,
           std::unique_ptr<const ConstraintEquations> constraints = nullptr,
           ConstraintOptions options = {});

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  const Body& body(int i) const { return bodies_[static_cast<std::size_t>(i)]; }
  const std::vector<Body>& bodies() const { return bodies_; }
  std::span<const std::unique_ptr<const ForceElement>> elements() const { return elements_; }
  /// Index of the body with this name, or −1.
  int body_index(const std::string& name) const;

  /// Sorted, unique known times where loads switch (time-profile ends).
  const std::vector<double>& discontinuities() const { return discontinuities_; }
  /// True when some element depends on velocities.
  bool has_velocity_dependent_loads() const { return velocity_dependent_; }
  FlexibleFormulation formulation() const { return formulation_; }
  bool has_flexible_bodies() const { return flexible_; }
  /// True when some element may dissipate (velocity-dependent loads) or a body has modal
  /// damping: integrators then track the dissipated work W_d (Trajectory::dissipated_work).
  bool dissipates() const { return dissipates_; }

  /// The scene's initial state made consistent with the ideal joints (positions by Newton
  /// projection, velocities by projection, in the mass metric), computed at each call — the model
  /// keeps no solve result — and how far it moved (0 without joints).
  ConsistentInitialState consistent_initial_state() const;
  /// consistent_initial_state().state: where every integrator starts.
  State initial_state() const { return consistent_initial_state().state; }
  Workspace make_workspace() const;

  /// Ideal joints (docs/joints.md): the constraint equations, or nullptr.
  bool has_constraints() const { return constraints_ != nullptr; }
  const ConstraintEquations* constraints() const { return constraints_.get(); }
  /// Where each body's (v_WBr, ω̄, q̇_f) sits in the stacked coordinates, and which of those rows
  /// it integrates: the one layout the joints, genalpha and the DAE form stack by.
  const VelocityLayout& velocity_layout() const { return layout_; }
  /// The independent constraint rows chosen at the scene's initial configuration (the others are
  /// redundant there: docs/joints.md): a constant of the scene, where every tracker starts.
  const std::vector<int>& independent_rows() const { return active_rows_; }
  /// A tracker at the start of an integration: the independent rows, no accepted state yet
  /// (core/constraint_tracker.hpp). Empty without joints.
  ConstraintTracker make_constraint_tracker() const;
  /// make_constraint_tracker()'s, kept: what evaluations without a tracker of their own read.
  const ConstraintTracker& initial_tracker() const { return default_tracker_; }
  /// Moves `tracker` to a state the integrator accepted (a step, an output, a restart), as far
  /// as `advance` says (core/constraint_tracker.hpp): the rows in force chosen again where they
  /// became ill-conditioned, the test for a singular configuration passed since its last
  /// accepted state, and the rows at this state kept as the next solves' reference
  /// (docs/joints.md, "Singular configurations"). J M⁻¹ Jᵀ is factored here (but for
  /// kReference), so integrators whose equations never factor it (IDA's index-2 form) get the
  /// singular-configuration tests from it. Throws SingularConfigurationError naming the joint
  /// and time, the tracker left as it was. Allocates only where rows are chosen again.
  void advance_tracker(S t, const State& state, ConstraintTracker& tracker, Workspace& ws,
                       TrackerAdvance advance = TrackerAdvance::kFull) const;
  /// The multipliers of the last constrained solve on ws (compute_accelerations,
  /// accelerations_from_wrenches) with the rows they belong to: a view, valid until ws's next
  /// evaluation.
  JointMultipliers joint_multipliers(const Workspace& ws) const {
    return JointMultipliers(ws.constraint);
  }
  /// Newton projection of the positions onto Φ(q, t) = 0 (mass metric; p_Br, θ by the body-frame
  /// rotation increment, q_f), then of the velocities onto J v + Φ_t = 0, on the tracker's rows
  /// (chosen again where ill-conditioned); without one, on the initial configuration's. Returns
  /// the largest relative violations before the projection.
  InitialProjection project(S t, State& state, const ConstraintTracker& tracker,
                            Workspace& ws) const;
  InitialProjection project(S t, State& state, Workspace& ws) const {
    return project(t, state, default_tracker_, ws);
  }
  /// The stacked generalized velocities (v_WBr, ω̄, q̇_f) of a state (velocity_layout()'s).
  void stack_velocities(const State& state, Vector& v) const { layout_.stack_velocities(state, v); }
  /// The projection of the velocities alone (positions consistent).
  void project_velocities(S t, State& state, const ConstraintTracker& tracker, Workspace& ws) const;
  /// The largest relative position violation of the joints at a state (length rows by the
  /// joints' length scale ℓ, rotation rows as they are: project's measure); 0 without joints.
  S relative_position_violation(S t, const State& state, Workspace& ws) const;
  /// The largest relative violations of all rows (the redundant ones included) at a state.
  RelativeJointViolationTpl<S> relative_joint_violation(S t, const State& state,
                                                        Workspace& ws) const;
  /// The rank of all the rows at a state (each row's rank decision relative to its own scale:
  /// independent_rows, at relative threshold `tolerance`); 0 without joints.
  int constraint_rank(S t, const State& state, Workspace& ws,
                      double tolerance = kRedundantRowTolerance) const;
  /// The joints' length scale ℓ (m): the largest arm from a body's Br to a joint point.
  S joint_length_scale() const { return joint_length_scale_; }
  /// Per joint: the largest |Φ| of its rows (m or rad) and of its velocity rows |J v + Φ_t| (m/s
  /// or rad/s) at a state.
  std::vector<std::array<S, 2>> constraint_violations(S t, const State& state, Workspace& ws) const;
  /// Whether the motion from `state` at t runs into a singular configuration of the joints within
  /// a short time: the positions advanced along the state's velocities (v, ω̄, q̇_f; prescribed
  /// motion and drives at the later times) by 1e-4, 1e-3, 1e-2 and 1e-1 of the mechanism's own time
  /// ℓ/|v| and by `step`, each accepted by a tracker of its own as a solver's states are
  /// (advance_tracker: a rank drop or the rows' orientation turning). Returns the
  /// SingularConfigurationError's message naming the joint, or "" when none is ahead. For the
  /// messages of integrators that fail at a dead point (IDA, genalpha). Allocates.
  std::string singular_configuration_ahead(S t, const State& state, S step) const;
  /// Per joint: the force and torque (about the joint point, world) it exerts on its first body,
  /// from the minimum-norm multipliers of all its rows at the state's accelerations (loads of
  /// the branch active at context.t_segment, the tracker's rows, no stabilization). Allocates:
  /// for outputs.
  std::vector<JointReaction> joint_reactions(const LoadContext& context, const State& state,
                                             const ConstraintTracker& tracker, Workspace& ws) const;
  std::vector<JointReaction> joint_reactions(const LoadContext& context, const State& state,
                                             Workspace& ws) const {
    return joint_reactions(context, state, default_tracker_, ws);
  }
  /// Accelerations sized for the model (modal parts included).
  Accelerations make_accelerations() const;
  /// Sets the rigid part of every prescribed body to its angle law's at time t (p_WBr fixed,
  /// v_WBr = 0, θ and ω̄ of the law). Other bodies are untouched.
  void apply_prescribed_motion(S t, State& state) const;
  /// The same, keeping the laws' α̅ at t in ws for the accelerations evaluated at t (one
  /// evaluation of each law instead of two: in quad its trigonometry is a large part of an
  /// evaluation).
  void apply_prescribed_motion(S t, State& state, Workspace& ws) const;

  /// Fills workspace.kinematics (A(θ) per body) and workspace.wrenches at (context, state); the
  /// receipt names them for the functions that read them.
  Loads compute_wrenches(const LoadContext& context, const State& state, Workspace& ws) const;
  /// compute_wrenches with each body's attitude matrix A(θ_i) given (R_WB, one per body): for a
  /// caller whose own kinematics formed the matrices that A(θ) would form again from θ (the joint
  /// form's forward kinematics, constraint/reduced_model.hpp). The state's θ are not read.
  Loads compute_wrenches(const LoadContext& context, const State& state,
                         std::span<const Eigen::Matrix<S, 3, 3>> R_WB, Workspace& ws) const;
  /// Accelerations from the loads compute_wrenches left in ws, the ideal joints enforced on the
  /// tracker's rows (core/constrained_solve_tpl.hpp) with Baumgarte's rate `stabilization` (1/s:
  /// J v̇ = γ − 2α (J v + Φ_t) − α² Φ makes the constraint manifold attracting for integrators
  /// that cannot project, reference/ode_form.hpp; 0, the plain index-1 form, changes nothing on
  /// the manifold). The multipliers, with their rows, are joint_multipliers(ws) afterwards.
  /// Throws SingularConfigurationError at a singular configuration.
  void accelerations_from_wrenches(const Loads& loads, const ConstraintTracker& tracker,
                                   Workspace& ws, Accelerations& accelerations,
                                   S stabilization = S(0)) const;
  /// The same on the rows chosen at the initial configuration (chosen again where they are
  /// ill-conditioned at the state), no stabilization: for models without joints and outputs.
  void accelerations_from_wrenches(const Loads& loads, Workspace& ws,
                                   Accelerations& accelerations) const {
    accelerations_from_wrenches(loads, default_tracker_, ws, accelerations);
  }
  /// compute_wrenches then accelerations_from_wrenches: a function of its arguments alone.
  Loads compute_accelerations(const LoadContext& context, const State& state,
                              const ConstraintTracker& tracker, Workspace& ws,
                              Accelerations& accelerations, S stabilization = S(0)) const;
  Loads compute_accelerations(const LoadContext& context, const State& state, Workspace& ws,
                              Accelerations& accelerations) const {
    return compute_accelerations(context, state, default_tracker_, ws, accelerations);
  }

  /// The generalized equations of body i as a residual at the given accelerations and the loads
  /// in ws (at loads.state()): the 6 + n rows M v − (Qe + Qv − [0; 0; Kq + Dq̇]) in the
  /// quasi-velocity variables (translation, rotation in the body frame, modes). The rows a
  /// pivot or prescribed body does not integrate are the reactions its constraint supplies.
  void dynamics_residual(int i, const Loads& loads, const BodyAcceleration& acc, Workspace& ws,
                         Eigen::Ref<Vector> out) const;
  /// ∂(dynamics_residual)/∂(a_WBr, α̅, q̈_f) of flexible body i, (6+n)², from the terms of the
  /// last dynamics_residual call on ws: [M_rr M_rf; M_rfᵀ m_ff] (LTE: no M_rf in the rigid
  /// rows, so not symmetric). Allocates nothing when `out` is sized.
  void residual_mass_matrix(int i, const Workspace& ws, Eigen::Ref<Matrix> out) const;
  /// The modal rows of a flexible body solved for q̈_f with the rigid accelerations given
  /// (a_WBr, α̅; a prescribed body uses a = 0 and its law's α̅ at the loads' time), the loads
  /// in ws and their state's q_f, q̇_f, ω̄. Under LTE this is the modal equation of
  /// docs/design/model.md, which the hybrid schemes integrate by central differences.
  void modal_accelerations(int i, const Loads& loads, const Vector3& a_WBr,
                           const Vector3& alpha_WB_B, Workspace& ws, Vector& qdd_f) const;
  /// α̅ of body i's angle law at time t (zero for a body not prescribed).
  Vector3 prescribed_alpha_WB_B(int i, S t) const;
  /// Torque about the axis that drives a prescribed body along its law (N·m): the axis
  /// component of the rotational reaction (dynamics_residual's rotation rows, to world) at the
  /// loads in ws.
  S driving_torque(int i, const Loads& loads, const BodyAcceleration& acc, Workspace& ws) const;

  S kinetic_energy(const State& state) const;
  /// Potential energy of the force elements plus the elastic energy ½ q_fᵀ K q_f.
  S potential_energy(const LoadContext& context, const State& state, Workspace& ws) const;
  /// Total number of switching functions of the force elements (contact gaps).
  int switching_function_count() const { return switching_count_; }
  /// All switching functions at a state, element by element (g has switching_function_count()
  /// entries). Allocates nothing.
  void switching_functions(const LoadContext& context, const State& state, Workspace& ws,
                           std::span<S> g) const;
  /// The force elements' clamp functions (ForceElementTpl::clamp_functions) in the layout of
  /// switching_functions: where each switching function's law changes branch.
  void clamp_functions(const LoadContext& context, const State& state, Workspace& ws,
                       std::span<S> c) const;
  /// compute_wrenches and, in the same pass over the elements, the rates of [W_d, extra
  /// integrals] (but the drives' power, which needs the accelerations: the caller adds it)
  /// (integral_rates' layout; empty span: none) and the switching and clamp functions
  /// (switching_function_count() each, or empty). For integrators that need all three at every
  /// evaluation (the precision references' event location). Allocates nothing.
  Loads compute_wrenches_and_rates(const LoadContext& context, const State& state, Workspace& ws,
                                   std::span<S> rates, std::span<S> g, std::span<S> c) const;
  /// Power dissipated by the force elements and the modal damping (q̇_fᵀ D q̇_f), W.
  S dissipated_power(const LoadContext& context, const State& state, Workspace& ws) const;
  /// Wear channels (one per contact element, core/model_integrals.cpp): their count, names
  /// (the contacts' names) and, for each switching function, its channel (−1: none).
  int wear_channel_count() const { return static_cast<int>(wear_names_.size()); }
  const std::vector<std::string>& wear_channel_names() const { return wear_names_; }
  const std::vector<int>& switching_channels() const { return switching_channels_; }
  /// Normal force, slip speed and friction power of every channel at a state (into ws.wear).
  void wear_samples(const LoadContext& context, const State& state, Workspace& ws) const;
  /// Worn depths (docs/wear.md): the states StateTpl::wear_depth holds, contact after contact in
  /// element order; per wear channel the first of its depths and their count (0 without a wear
  /// law), its law (nullptr without) and the scar area of each depth (m²).
  int wear_depth_count() const { return wear_depth_count_; }
  int channel_depth_first(int channel) const {
    return static_cast<int>(element_depth_first_[static_cast<std::size_t>(
        wear_elements_[static_cast<std::size_t>(channel)])]);
  }
  int channel_depth_count(int channel) const {
    return elements_[static_cast<std::size_t>(wear_elements_[static_cast<std::size_t>(channel)])]
        ->wear_depth_count();
  }
  const WearLaw* channel_wear_law(int channel) const {
    return elements_[static_cast<std::size_t>(wear_elements_[static_cast<std::size_t>(channel)])]
        ->wear_law();
  }
  /// The scar area of each depth, m² (wear_depth_count() entries).
  const std::vector<double>& wear_depth_areas() const { return wear_depth_areas_; }
  /// ḣ of every depth at a state (wear_depth_count() entries), m/s. Allocates nothing.
  void wear_depth_rates(const LoadContext& context, const State& state, Workspace& ws,
                        std::span<S> rates) const;
  /// The worn volume Σ area·h of a channel's depths at a state, m³.
  S wear_volume(int channel, const State& state) const;
  /// The largest of a channel's depths at a state, m (0 without a wear law).
  S wear_depth_max(int channel, const State& state) const;
  /// True when the model integrates the work of its applied loads (ForceElement::
  /// tracks_applied_work: every prescribed force) — when it tracks work at all (tracks_work).
  bool tracks_applied_work() const { return tracks_work() && applied_work_; }
  /// True when an ideal joint is driven (its drive does work: W_drive) and the model tracks it.
  bool tracks_drive_work() const { return drive_work_; }
  /// True when every integrator tracks [W_d, extra integrals]: the model dissipates, or a drive
  /// does work (docs/output.md, "Energy balance"). The balance E + W_d − W_a − W_drive is then
  /// in the outputs and, where nothing else feeds energy in, constant.
  bool tracks_work() const { return dissipates_ || drive_work_; }
  /// Integrals every integrator tracks after W_d when the model tracks work (0 otherwise), in
  /// integral_layout()'s order.
  int extra_integral_count() const {
    return integral_layout_.count > 0 ? integral_layout_.count - 1 : 0;
  }
  /// Where each tracked integral sits in integral_rates' [W_d, extra integrals]: the one
  /// description every integrator, output and monitor reads.
  const IntegralLayout& integral_layout() const { return integral_layout_; }
  /// Rates of [W_d, extra integrals] at a state (integral_layout().count entries): the
  /// dissipated power, the applied power, the drives' power, each channel's |F_t·v_t|.
  /// `constraint_force`: the stacked generalized force of the ideal joints −J_aᵀλ at this state
  /// from the caller's own constrained solve (JointMultipliers::force after
  /// compute_accelerations), or null to solve for it here (one more evaluation) on `tracker`'s
  /// rows (null: the initial configuration's). Allocates nothing.
  void integral_rates(const LoadContext& context, const State& state, Workspace& ws,
                      std::span<S> rates, const Vector* constraint_force = nullptr,
                      const ConstraintTracker* tracker = nullptr) const;
  /// Power of the ideal joints' reactions on the bodies, F_cᵀ v (W), F_c the stacked
  /// generalized constraint force: the drives' power (the other rows do no work on their
  /// manifold; off it, the reactions' work on the drift).
  S constraint_power(const State& state, const Vector& constraint_force, Workspace& ws) const;
  /// ½ Σ q_fᵀ K q_f over the flexible bodies.
  S elastic_energy(const State& state) const;
  /// Total linear momentum, world.
  Vector3 linear_momentum_W(const State& state) const requires std::is_same_v<S, double>;
  /// Total angular momentum about the world origin, world.
  Vector3 angular_momentum_W(const State& state) const requires std::is_same_v<S, double>;

  /// Frame origin Bo of body i (the CSV's B.x, B.y, B.z) and its velocity.
  Vector3 p_WBo(int i, const BodyState& s) const;
  Vector3 v_WBo(int i, const BodyState& s) const;
  /// World position of a body point given from the frame origin.
  Vector3 p_WP(int i, const BodyState& s, const Eigen::Vector3d& p_BoP_B) const;
  /// World position of a tracked point, deformed when it is a node of a flexible body.
  Vector3 p_WP(int i, const BodyState& s, const TrackedPoint& point) const;

 private:
  /// The scene's initial state as described (before any projection onto the joints).
  State scene_initial_state() const;
  /// With joints: the independent rows and length scale at the scene's initial state, then the
  /// checks that it can be made consistent (see the constructor).
  void assemble_initial_state(const ConstraintOptions& options);
  /// Points ws.kinematics at the state (A(θ), and the q_f the loads see) and ws.wear_depth at
  /// its worn depths; throws std::invalid_argument when the state has not wear_depth_count() of
  /// them.
  void pose_bodies(const State& state, Workspace& ws) const;
  /// pose_bodies with A(θ_i) = R_WB[i] given (compute_wrenches' second form); null: from θ.
  void pose_bodies(const State& state, const Eigen::Matrix<S, 3, 3>* R_WB, Workspace& ws) const;
  /// The elements' wrenches at the bodies posed in ws (compute_wrenches after pose_bodies).
  Loads posed_wrenches(const LoadContext& context, const State& state, Workspace& ws) const;
  /// `context` with element e's slice of the posed depths (ws.wear_depth).
  LoadContext element_context(const LoadContext& context, const Workspace& ws,
                              std::size_t e) const {
    LoadContext c = context;
    const auto count = static_cast<std::size_t>(elements_[e]->wear_depth_count());
    if (count > 0) c.wear_depth = ws.wear_depth.subspan(element_depth_first_[e], count);
    return c;
  }
  void flexible_system(int i, const BodyState& s, Workspace& ws) const;
  /// α̅ of body i's angle law at t, from ws's memo where it holds t's.
  Vector3 prescribed_alpha_WB_B(int i, S t, const Workspace& ws) const;
  /// Calls evaluate(element, its span of `out`) for each element with switching functions, in
  /// the order that numbers them (switching_functions' layout).
  template <typename Evaluate>
  void for_each_switching_element(std::span<S> out, Evaluate&& evaluate) const;
  /// Σ q̇_fᵀ D q̇_f over the flexible bodies (the modal damping's part of dissipated_power).
  S modal_dissipated_power(const State& state) const;
  /// The elements' applied power at the bodies posed in ws (the rate of W_a).
  S applied_power(const LoadContext& context, const Workspace& ws) const;
  /// apply_prescribed_motion, with the laws' α̅ into `alpha` when given.
  void set_prescribed_motion(S t, State& state, std::vector<Vector3>* alpha) const;
  void flexible_accelerations(int i, S t, const BodyState& s, Workspace& ws,
                              BodyAcceleration& a) const;
  /// Each body's accelerations from its loads alone (M⁻¹ Q), before the joints' reactions.
  void free_accelerations(const Loads& loads, Workspace& ws, Accelerations& accelerations) const;
  /// M_b⁻¹ rhs for body b (rigid: its diag(m, I_Br) inverse; flexible: the structured solve
  /// factored by the last accelerations_from_wrenches), with the rows its motion fixes zero.
  void apply_inverse_mass(int b, const Eigen::Ref<const Vector>& rhs, Eigen::Ref<Vector> out,
                          Workspace& ws) const;
  /// The ideal joints' multipliers and constrained accelerations at the loads in ws, on the
  /// tracker's rows, with Baumgarte's rate `stabilization`.
  void apply_constraints(S t, const State& state, const ConstraintTracker& tracker, S stabilization,
                         Workspace& ws, Accelerations& accelerations) const;
  /// The rows at a state, and their factorization in the mass metric (flexible bodies' factors
  /// at the state) on the tracker's rows (chosen again where ill-conditioned), without the
  /// orientation test; throws SingularConfigurationError at a singular configuration.
  void factor_constraints_at(S t, const State& state, const ConstraintTracker& tracker,
                             Workspace& ws) const;
  /// Poses the bodies at the state and factors their flexible bodies' mass matrices and the
  /// joints' rows there (the common part of factor_constraints_at and advance_tracker).
  void evaluate_rows_at(S t, const State& state, Workspace& ws) const;
  /// M⁻¹ rhs over the stacked coordinates, body by body (apply_inverse_mass); out sized N.
  void stacked_inverse_mass(const Vector& in, Vector& out, Workspace& ws) const;
  /// Largest relative violation of the position rows (length rows by the joints' length scale)
  /// and of the velocity rows (by the bodies' speeds), from s.rows at `state`; s.v and s.rate
  /// are its scratch.
  RelativeJointViolationTpl<S> relative_violation(ConstraintSolveTpl<S>& s,
                                                  const State& state) const;
  /// Adds the stacked increment δ = (δp_Br, δφ_B, δq_f) to the positions: p ← p + δp, θ ← θ ⊗
  /// exp(δφ) (renormalized), q_f ← q_f + δq_f; bodies whose motion is prescribed keep theirs.
  void apply_position_increment(const Vector& delta, State& state) const;
  /// The rows at the scene's initial configuration refused when double cannot resolve them
  /// (JointDataError): not finite, or a joint point beyond kJointArmLimit radii of gyration of
  /// its body.
  void check_joint_data(const ConstraintRowsTpl<S>& rows) const;
  /// After the projection of the initial state: every row (the redundant ones included)
  /// reached, positions (and with `velocities` the velocity rows), else
  /// InconsistentInitialStateError with each joint's residual.
  void check_projection_reached(const State& state, Workspace& ws, double tolerance,
                                bool velocities) const;
  /// With rows set aside as dependent at the initial configuration: that they stay dependent and
  /// satisfied a small motion away (structural redundancy, as a planar loop's out-of-plane rows)
  /// rather than gaining rank (a singular start: a dead centre, a tangency), which throws
  /// SingularConfigurationError naming the joint.
  void check_singular_start(const State& state, Workspace& ws) const;

  std::vector<Body> bodies_;
  std::vector<std::unique_ptr<const ForceElement>> elements_;
  std::vector<double> discontinuities_;
  bool velocity_dependent_ = false;
  FlexibleFormulation formulation_ = FlexibleFormulation::kCoupled;
  bool flexible_ = false;
  int switching_count_ = 0;
  bool dissipates_ = false;
  std::vector<std::string> wear_names_;
  std::vector<int> wear_elements_;     ///< element index of each channel
  std::vector<int> element_channels_;  ///< the wear channel of each element (−1: none)
  std::vector<int> switching_channels_;
  int wear_depth_count_ = 0;
  std::vector<std::size_t> element_depth_first_;  ///< per element: its first depth
  std::vector<double> wear_depth_areas_;
  bool applied_work_ = false;
  bool drive_work_ = false;
  IntegralLayout integral_layout_;
  std::unique_ptr<const ConstraintEquations> constraints_;
  VelocityLayout layout_;
  std::vector<int> active_rows_;
  /// make_constraint_tracker(): what the evaluations without a tracker of their own read.
  ConstraintTracker default_tracker_;
  S joint_length_scale_ = S(1);  ///< the joints' largest arm from a body's Br (m)
};

using Model = ModelTpl<double>;
extern template class ModelTpl<double>;

}  // namespace flexref::core
