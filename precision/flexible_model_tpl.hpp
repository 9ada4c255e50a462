#pragma once
/// \file flexible_model_tpl.hpp
/// One flexible body of docs/design/model.md in precision S (double, long double,
/// boost::multiprecision::float128): free, pivot or prescribed rigid motion, the coupled
/// floating-frame model or the LTE model, modal stiffness and damping, geometric stiffening,
/// uniform gravity and the applied forces (at hub points or nodes) and torques of a scene with
/// their time profiles. The equations are core::Model's and the evaluation is the one of
/// flexible/ (inertia_terms_tpl.hpp, mass_matrix_solve_tpl.hpp, modal_invariants_tpl.hpp), the
/// same templates the double model runs, here instantiated in S. Internal to precision/:
/// instantiated in flexible_model_tpl.cpp for the three precisions.
///
/// The data are the scene's double numbers (masses, node positions, mode shapes, modal
/// stiffness and damping ratios, geometric stiffness matrices), exact in S; everything derived
/// from them — the reference point Br (the undeformed centre of mass of a free body), the
/// invariants about it, the modal damping 2ζ_i√(K_i μ_i), m_ff's Cholesky factor — is formed in
/// S, so the model solved is the exact model of the data.
///
/// State (non-prescribed): p_WBr (3), θ_WB (4), v_WBr (3), ω̄ (3), q_f (n), q̇_f (n), then the
/// integrals (W_d, W_a) when the model dissipates. A prescribed body integrates q_f and q̇_f
/// only; its attitude, ω̄ and α̅ are its angle law's at t (core/prescribed_motion.hpp, in S).
/// Equations (model.md, quasi-velocity form, about Br, v = (a_WBr, α̅, q̈_f)):
///   coupled: M(θ, q_f) v = Qe + Qv − [0; 0; K q_f + D q̇_f],  θ̇ = ½ θ ⊗ (0, ω̄),
///   LTE:     the same blocks at q_f = 0, q̇_f = 0, no M_rf in the rigid rows, loads on the
///            undeformed body (attachments at nodes see the deformation: node_attachment.hpp),
/// with the known rows (pivot: a = 0; prescribed: a = 0, α̅ of the law) moved to the right.
/// Gap supports at nodes (contact/gap_support.hpp) push the deformed node back into its
/// clearance, and spheres at hub points or nodes on ground planes (contact/contact.hpp) off the
/// plane, with their normal and friction laws, evaluated in S; their dissipation enters W_d and
/// their friction power each wear channel's work. Point-charge potentials
/// (core/point_charge_potential.hpp) act at hub points, and their V enters the energy.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "contact/contact_laws.hpp"
#include "contact/gap_support_tpl.hpp"
#include "contact/penalty_load_tpl.hpp"
#include "core/model.hpp"
#include "core/point_charge_potential.hpp"
#include "core/prescribed_motion.hpp"
#include "core/time_profile.hpp"
#include "flexible/mass_matrix_solve_tpl.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::precision {

template <typename S>
class FlexibleModelTpl {
 public:
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Quaternion = Eigen::Matrix<S, 4, 1>;

  /// Throws std::invalid_argument naming the first part of the scene this model does not carry
  /// (more than one body, sphere–sphere contacts, joints).
  FlexibleModelTpl(const scene::SceneSpec& spec, core::FlexibleFormulation formulation);

  /// True when the scene has a flexible body (this model's scenes).
  static bool applies_to(const scene::SceneSpec& spec);

  int state_size() const { return rigid_size() + 2 * n_ + integral_count_; }
  /// The double model's studies::trajectory_columns ("t" first): output_row fills the rest.
  const std::vector<std::string>& columns() const { return columns_; }
  int mode_count() const { return n_; }
  /// Two per gap support or sphere–plane pair, in the double model's order: the gap g (it
  /// pushes while g < 0; its sign change is an onset or a release) and the unclamped law's value
  /// (NormalLaw::clamp_function).
  int switching_function_count() const { return 2 * static_cast<int>(supports_.size()); }
  void switching_functions(S t, const std::vector<S>& y, std::vector<S>& values) const;
  int wear_channel_count() const { return static_cast<int>(wear_channels_.size()); }
  /// The wear channel of a gap support or pair, −1 for an unnamed one.
  int wear_channel_of_pair(int pair) const {
    return supports_[static_cast<std::size_t>(pair)].channel;
  }
  /// Times where a load profile switches, and the end of a spin-up law (φ⁗ jumps there: φ̈ =
  /// (Ω/T)(1 − cos 2πt/T) before, 0 after; extrapolation's high orders need the stop).
  std::vector<double> discontinuities() const;

  std::vector<S> initial_state() const;
  /// ẏ = f(t, y) on the load branch active at t_segment. Uses the model's scratch: one
  /// evaluation at a time (the integrators here are sequential).
  void derivative(const std::vector<S>& y, std::vector<S>& dydt, S t, double t_segment,
                  std::vector<S>* switching = nullptr) const;
  /// Kinetic + gravitational + elastic energy at (t, y) (the `energy` column).
  S energy(S t, const std::vector<S>& y) const;
  /// The trajectory_columns row at (t, y) after `t`: p_WBo, θ, v_WBo, ω̄, tracked points (nodes
  /// deformed), q_f, q̇_f, the drive torque of a prescribed body, the energy, and when the model
  /// dissipates W_d, (W_a), E − E(0) + W_d − W_a; per wear channel F_n, the slip speed, the wear
  /// work and `impacts` (the caller's onset counts, one per channel; empty: none yet).
  std::vector<S> output_row(S t, const std::vector<S>& y,
                            const std::vector<double>& impacts = {}) const;

 private:
  struct Pose {
    Vector3 p_WBr;
    Quaternion theta_WB;
    Matrix3 A;
    Vector3 v_WBr;
    Vector3 w_B;
    Vector3 alpha_B;  ///< the law's α̅ (prescribed only)
  };
  struct Attachment {
    Vector3 p_BrP_B;  ///< undeformed, from Br
    int node = -1;
    Eigen::Matrix<S, 3, Eigen::Dynamic> phi_B;  ///< Φ_k (3×n); empty for a hub point
  };
  struct Load {
    bool torque = false;
    Vector3 value;
    bool world_frame = true;
    Attachment at;
    core::TimeProfile profile = core::TimeProfile::constant();
    bool tracks_work = false;
  };
  /// A gap support at a node (contact/gap_support.hpp), or a sphere of radius r at `at` on the
  /// ground plane through Q with unit normal n (contact/contact.hpp), its geometry in S.
  struct Support {
    Attachment at;
    bool sphere = false;
    contact::GapGeometryTpl<S> geometry;  ///< gap support
    S radius = S(0);                      ///< sphere
    Vector3 p_WQ = Vector3::Zero();       ///< sphere: a point of the plane
    Vector3 n_W = Vector3::UnitZ();       ///< sphere: the plane's unit normal
    contact::NormalLaw normal;
    contact::FrictionLaw friction;
    int channel = -1;
  };
  /// What a support applies at a state (GapSupport::Evaluation in S).
  struct SupportLoad {
    S gap = S(0);
    S clamp = S(0);   ///< NormalLaw::clamp_function(δ, δ̇)
    Vector3 r_W;      ///< the point of application (deformed node, sphere's P) from p_WBr
    Vector3 f_W;      ///< F_n n + F_t, zero when it does not push
    S normal = S(0);  ///< F_n ≥ 0
    S slip_speed = S(0);
    S dissipated_power = S(0);
    S wear_power = S(0);  ///< |F_t·v_t|
  };
  struct Scratch {
    flexible::InertiaTermsTpl<S> terms;
    flexible::MassSolveScratchTpl<S> solve;
    Vector q, qd, zero, Q_f, rhs, x;
    Vector3 f_W, tau_W;
    S applied_power;
    S contact_dissipation;
    std::vector<S> wear_power;  ///< per wear channel
    std::vector<S> switching;   ///< the supports' switching values of the last evaluation
  };

  int rigid_size() const { return prescribed() ? 0 : 13; }
  bool prescribed() const { return motion_ == core::MotionKind::kPrescribed; }
  Pose pose(S t, const std::vector<S>& y) const;
  /// The loads, the inertia terms, the right-hand side and the solved accelerations x (6+n)
  /// at (t, y) into scratch_.
  void evaluate(S t, double t_segment, const Pose& p) const;
  Vector3 attached_offset_W(const Attachment& a, const Pose& p) const;
  /// A support's gap, clamp function and load at the pose (q_f, q̇_f in the scratch).
  SupportLoad support_load(const Support& support, const Pose& p) const;
  /// Where a support acts at the pose (q_f in the scratch): its gap, its unit normal and the
  /// point of application from p_WBr (the deformed node; a sphere's contact point P).
  struct SupportPoint {
    S gap;
    Vector3 n_W;
    Vector3 r_W;
  };
  SupportPoint support_point(const Support& support, const Pose& p) const;
  /// A point-charge potential's law and its charges' hub points (the weights are the law's).
  struct Potential {
    core::PointChargePotential law;
    std::vector<Attachment> at;
  };
  /// Charge i's arm from p_WBr, force c_i f_unit and potential c_i V_unit at the pose.
  struct ChargeLoad {
    Vector3 r_W;
    Vector3 f_W;
    S potential;
  };
  ChargeLoad charge_load(const Potential& potential, std::size_t i, const Pose& p) const;
  /// q_f and q̇_f of y into the scratch.
  void load_modes(const std::vector<S>& y) const;
  /// s_t(q) = s0 + S q (+ Δs(q) with geometric stiffening), the first moment about Br.
  Vector3 first_moment(const Vector& q) const;

  std::string name_;
  core::MotionKind motion_ = core::MotionKind::kFree;
  core::FlexibleFormulation formulation_ = core::FlexibleFormulation::kCoupled;
  int n_ = 0;
  flexible::ModalInvariantsTpl<S> invariants_;  ///< about Br, hub included
  flexible::ModalMassFactorTpl<S> factor_;
  Vector stiffness_;
  Vector damping_;
  Vector3 p_BoBr_B_;
  core::PrescribedRotation prescribed_;
  Vector3 axis_W_;
  Quaternion theta0_;  ///< the initial attitude, normalized in S
  Vector3 p_WBo0_;     ///< the initial frame origin (a prescribed body's fixed Bo = Br)
  std::vector<S> initial_;
  std::vector<Attachment> points_;
  std::vector<Load> loads_;
  std::vector<Support> supports_;
  std::vector<Potential> potentials_;
  std::vector<std::string> wear_channels_;
  Vector3 g_W_;
  std::vector<std::string> columns_;
  std::vector<double> discontinuities_;
  bool dissipates_ = false;
  bool applied_work_ = false;
  int integral_count_ = 0;
  S energy0_ = S(0);
  mutable Scratch scratch_;
};

}  // namespace flexref::precision
