#pragma once
/// \file multibody_model_tpl.hpp
/// The bodies of a scene, rigid and flexible, and everything between them, in precision S
/// (double, long double, boost::multiprecision::float128): free, pivot or prescribed rigid
/// motion of each body, the coupled floating-frame model or the LTE model of each flexible body
/// (modal stiffness and damping, geometric stiffening), uniform gravity, applied forces (at hub
/// points or nodes) and torques with their time profiles, point-charge potentials, gap supports,
/// sphere–plane and sphere–sphere contacts (spheres at hub points or nodes), and spherical and
/// revolute bushings between bodies or to the ground, and ideal joints (constraint/, the
/// multipliers by core/constrained_solve_tpl.hpp). The equations are core::Model's, written
/// once: each body's rows are core/body_equations_tpl.hpp's over flexible/ (inertia_terms_tpl.hpp,
/// mass_matrix_solve_tpl.hpp, modal_invariants_tpl.hpp), and the loads are the double model's
/// force elements themselves, class templates converted to S (element_conversion.hpp;
/// core::ForceElementTpl). A rigid body is a body without modes (its invariants are its mass,
/// first and second moments about Br; M_rr and Qv are then Newton–Euler's).
/// Internal to precision/: instantiated in multibody_model_tpl.cpp for the three precisions.
///
/// The data are the scene's double numbers (masses, inertias, node positions, mode shapes,
/// modal stiffness and damping ratios, geometric stiffness matrices), exact in S; everything
/// derived from them — each reference point Br (the undeformed centre of mass of a free body),
/// the invariants about it, the modal damping 2ζ_i√(K_i μ_i), m_ff's Cholesky factor, the unit
/// vectors of the data (core/unit_vector_tpl.hpp) — is formed in S, so the model solved is the
/// exact model of the data.
///
/// State, body after body: p_WBr (3), θ_WB (4), v_WBr (3), ω̄ (3) unless the body is
/// prescribed (its attitude, ω̄ and α̅ are its angle law's at t, core/prescribed_motion.hpp, in
/// S), then q_f (n), q̇_f (n); then the integrals (W_d, W_a, each wear channel's work) when the
/// model dissipates. Equations of each body (model.md, quasi-velocity form, about Br,
/// v = (a_WBr, α̅, q̈_f)):
///   coupled: M(θ, q_f) v = Qe + Qv − [0; 0; K q_f + D q̇_f],  θ̇ = ½ θ ⊗ (0, ω̄),
///   LTE:     the same blocks at q_f = 0, q̇_f = 0, no M_rf in the rigid rows, loads on the
///            undeformed body (attachments at nodes see the deformation: node_attachment.hpp),
/// with the known rows (pivot: a = 0; prescribed: a = 0, α̅ of the law) moved to the right.
/// A force f at a world point P attached to a body enters its equations as f, (P − p_WBr) × f
/// and, at node k, Φ_kᵀ Aᵀ f (core/node_attachment.hpp); a contact pushes its second body
/// along +n and its first (a sphere–sphere pair) along −n at the contact point, a bushing its
/// first end with f at the midpoint M and its second with −f (contact/bushing.hpp).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/prescribed_motion.hpp"
#include "flexible/mass_matrix_solve_tpl.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::precision {

template <typename S>
class MultibodyModelTpl {
 public:
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Quaternion = Eigen::Matrix<S, 4, 1>;

  /// Every scene scene::build_model builds (which validates its modal data). Throws
  /// std::invalid_argument for what build_model refuses and for a force element of a kind this
  /// model does not know (none of build_model's today).
  /// With ideal joints, output_spacing (s, 0: none given) sets the Baumgarte rate the double
  /// ODE references use (reference::constraint_stabilization_rate), and the initial state is the
  /// double model's consistent one refined by Newton projection in S (project).
  MultibodyModelTpl(const scene::SceneSpec& spec, core::FlexibleFormulation formulation,
                    double output_spacing = 0.0);

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  /// The first slot of body i in the state.
  int body_offset(int i) const { return body(i).offset; }
  /// False for a prescribed body (no rigid slots: its law gives them).
  bool integrates_rigid_motion(int i) const {
    return body(i).motion != core::MotionKind::kPrescribed;
  }
  int mode_count(int i = 0) const { return body(i).n; }
  /// A body's mass, centre of mass from Br and inertia about Br (body frame), hub and nodes
  /// included, formed in S (the exact solutions' data: exact_high_precision.cpp).
  struct MassProperties {
    S mass;
    Vector3 c_B;
    Matrix3 J_Br_B;
  };
  MassProperties mass_properties(int i) const {
    const flexible::ModalInvariantsTpl<S>& inv = body(i).invariants;
    return {inv.mass, inv.s0 / inv.mass, inv.I0};
  }
  int state_size() const { return integrals_offset_ + integral_count_; }
  /// The double model's trajectory::trajectory_columns ("t" first): output_row fills the rest.
  const std::vector<std::string>& columns() const { return columns_; }
  /// Two per switching function of the force elements (a gap support's or contact pair's gap),
  /// in the double model's element order: the gap g (it
  /// pushes while g < 0; its sign change is an onset or a release) and the unclamped law's value
  /// (NormalLaw::clamp_function).
  int switching_function_count() const { return 2 * gap_count_; }
  void switching_functions(S t, const std::vector<S>& y, std::vector<S>& values) const;
  int wear_channel_count() const { return static_cast<int>(wear_channels_.size()); }
  /// The wear channel of a gap support or pair, −1 for an unnamed one.
  int wear_channel_of_pair(int pair) const {
    return pair_channels_[static_cast<std::size_t>(pair)];
  }
  /// Times where a load profile switches, and the end of each spin-up law (φ⁗ jumps there: φ̈ =
  /// (Ω/T)(1 − cos 2πt/T) before, 0 after; extrapolation's high orders need the stop).
  std::vector<double> discontinuities() const;

  std::vector<S> initial_state() const;

  /// Ideal joints (docs/joints.md, "Extended and quad precision"): the double model's equations
  /// in S (constraint::IdealJointsTpl), their multipliers by core/constrained_solve_tpl.hpp.
  bool has_constraints() const { return joints_ != nullptr; }
  /// Baumgarte's rate α (1/s) in the accelerations (core::Workspace::constraint_stabilization):
  /// J v̇ = γ − 2α (J v + Φ_t) − α² Φ; 0: the plain index-1 form.
  S constraint_stabilization() const { return stabilization_; }
  void set_constraint_stabilization(S alpha) { stabilization_ = alpha; }
  /// Newton projection of the positions in y onto Φ(q, t) = 0 in the mass metric, then of the
  /// velocities onto J v + Φ_t = 0 (core::Model::project in S), to S's round-off. Returns the
  /// largest relative position violation (length rows by the joints' length scale) before it.
  S project(S t, std::vector<S>& y) const;
  /// The largest relative position violation of the joints at (t, y) (as project's).
  S relative_position_violation(S t, const std::vector<S>& y) const;
  /// ẏ = f(t, y) on the load branch active at t_segment. Uses the model's scratch: one
  /// evaluation at a time (the integrators here are sequential).
  void derivative(const std::vector<S>& y, std::vector<S>& dydt, S t, double t_segment,
                  std::vector<S>* switching = nullptr) const;
  /// Kinetic + gravitational + elastic + the potentials', contacts' and bushings' energy at
  /// (t, y) (the `energy` column).
  S energy(S t, const std::vector<S>& y) const;
  /// The trajectory_columns row at (t, y) after `t`: per body p_WBo, θ, v_WBo, ω̄, tracked points
  /// (nodes deformed), q_f, q̇_f and a prescribed body's drive torque; the energy, and when the
  /// model dissipates W_d, (W_a), E − E(0) + W_d − W_a; per wear channel Σ F_n, the slip speed of
  /// its most loaded support or pair, the wear work and `impacts` (the caller's onset counts, one
  /// per channel; empty: none yet).
  std::vector<S> output_row(S t, const std::vector<S>& y,
                            const std::vector<double>& impacts = {}) const;

 private:
  /// A point of a body from its Br in the undeformed body frame, moving with node k's Φ_k q_f
  /// when it is attached to a node; body −1 is the ground (the point then in world).
  struct Attachment {
    int body = -1;
    Vector3 p_BrP_B = Vector3::Zero();
    int node = -1;
    Eigen::Matrix<S, 3, Eigen::Dynamic> phi_B;  ///< Φ_k (3×n); empty for a hub point
  };
  struct Body {
    std::string name;
    core::MotionKind motion = core::MotionKind::kFree;
    int n = 0;                                   ///< modes (0 for a rigid body)
    int offset = 0;                              ///< first slot in the state
    flexible::ModalInvariantsTpl<S> invariants;  ///< about Br, hub (rigid part) included
    flexible::ModalMassFactorTpl<S> factor;
    /// J_Br⁻¹, the inverse of invariants.I0 (a rigid body not prescribed: its Newton–Euler rows).
    Matrix3 J_Br_inv = Matrix3::Zero();
    Vector stiffness;
    Vector damping;
    Vector3 p_BoBr_B = Vector3::Zero();
    core::PrescribedRotation prescribed;
    Vector3 axis_W = Vector3::UnitZ();  ///< the prescribed axis, a unit vector of S
    Quaternion theta0;                  ///< the initial attitude, normalized in S
    Vector3 p_WBo0 = Vector3::Zero();   ///< the initial frame origin (a prescribed body's Bo = Br)
    std::vector<S> initial;             ///< its slots of the initial state
    std::vector<Attachment> points;     ///< tracked points
  };
  /// One body's evaluation: its state at (t, y) and its solved accelerations x = (a_WBr, α̅,
  /// q̈_f); its pose and loads are Scratch::kinematics[i] and Scratch::wrenches[i].
  struct BodyScratch {
    core::BodyStateTpl<S> state;
    Vector3 alpha_B = Vector3::Zero();  ///< the law's α̅ (prescribed only)
    flexible::InertiaTermsTpl<S> terms;
    flexible::MassSolveScratchTpl<S> solve;
    Vector zero, rhs, x;
  };
  struct Scratch {
    std::vector<BodyScratch> bodies;
    /// Each body's pose as the force elements see it (the q_f of the loads: zero under LTE) and
    /// the loads on it, one entry per body (the elements' spans).
    std::vector<core::BodyKinematicsTpl<S>> kinematics;
    std::vector<core::WrenchTpl<S>> wrenches;
    S applied_power = S(0);
    S dissipation = S(0);                      ///< the elements' dissipated power
    std::vector<S> wear_power;                 ///< per wear channel
    std::vector<S> switching;                  ///< the switching values of the last evaluation
    std::vector<S> gaps;                       ///< the elements' switching functions, in order
    std::vector<S> clamps;                     ///< their clamp functions
    std::vector<core::WearSampleTpl<S>> wear;  ///< per wear channel
    core::ConstraintSolveTpl<S> constraint;    ///< the ideal joints' solve (empty without)
  };

  const Body& body(int i) const { return bodies_[static_cast<std::size_t>(i)]; }
  /// Poses, q_f and q̇_f of every body at (t, y) into the scratch.
  void load_state(S t, const std::vector<S>& y) const;
  /// The loads of every body into the scratch (the integrals' rates and the switching values
  /// with them), then each body's inertia terms, right-hand side and solved accelerations x.
  void evaluate(S t, double t_segment) const;
  /// The attached point's offset A (x_P − p_BoBr + Φ_k q_f) from its body's p_WBr.
  Vector3 offset_W(const Attachment& a) const;
  Vector3 position_W(const Attachment& a) const;
  /// The elements' switching functions (gaps) and clamp functions at the scratch's state,
  /// interleaved into `values` (switching_functions' layout).
  void switching_values(const core::LoadContextTpl<S>& context, std::vector<S>& values) const;
  /// The scratch's gaps and clamps interleaved into `values` (g_0, c_0, g_1, c_1, …).
  void interleave_switching(std::vector<S>& values) const;
  /// Each wear channel's sample (its element's wear_samples) at the scratch's state.
  void sample_wear(const core::LoadContextTpl<S>& context) const;
  /// M_b⁻¹ rhs for body b (core::Model::apply_inverse_mass): a rigid body's diag(m, J_Br)
  /// inverse, a flexible body's structured solve factored by the last evaluate; the rows its
  /// motion fixes zero.
  void apply_inverse_mass(int b, const Eigen::Ref<const Vector>& rhs, Eigen::Ref<Vector> out) const;
  /// After evaluate at t: the joints' rows at the scratch's state, the stacked velocities
  /// (constraint.v) and, with stabilize, Baumgarte's terms; then the constrained accelerations
  /// into each body's x, the multipliers and the generalized constraint force into the
  /// constraint scratch (core::Model::apply_constraints).
  void apply_constraints(S t, bool stabilize) const;
  /// Loads the state, evaluates it (the flexible bodies' mass factors) and factors the joints'
  /// rows there; throws core::SingularConfigurationError at a singular configuration.
  void factor_constraints_at(S t, const std::vector<S>& y) const;
  /// The elements' context at (t, t_segment).
  core::LoadContextTpl<S> context(S t, double t_segment) const { return {t, t_segment}; }

  core::FlexibleFormulation formulation_ = core::FlexibleFormulation::kCoupled;
  std::vector<Body> bodies_;
  /// The double model's force elements, in its order, converted to S (element_conversion.hpp).
  std::vector<std::unique_ptr<const core::ForceElementTpl<S>>> elements_;
  int gap_count_ = 0;               ///< Σ the elements' switching functions
  std::vector<int> pair_channels_;  ///< the wear channel of each (−1: none)
  std::vector<std::string> wear_channels_;
  std::vector<std::size_t> wear_elements_;  ///< the element of each wear channel
  std::vector<int> element_channels_;       ///< the wear channel of each element (−1: none)
  std::vector<std::string> columns_;
  std::vector<double> discontinuities_;
  bool dissipates_ = false;
  bool applied_work_ = false;
  bool has_prescribed_ = false;
  int integrals_offset_ = 0;
  int integral_count_ = 0;
  S energy0_ = S(0);
  /// The ideal joints in S (nullptr without), where each body's (v_WBr, ω̄, q̇_f) sits in their
  /// stacked velocities, the joints' length scale ℓ (m) and Baumgarte's rate (1/s).
  std::unique_ptr<const core::ConstraintEquationsTpl<S>> joints_;
  core::VelocityLayout layout_;
  S joint_length_scale_ = S(1);
  S stabilization_ = S(0);
  mutable Scratch scratch_;
};

}  // namespace flexref::precision
