#pragma once
/// \file ode_system.hpp
/// The precision references' ODE y' = f(t, y) on a flat vector of S (double, long double,
/// boost::multiprecision::float128), for Boost.Odeint and the event location of
/// switched_integration.hpp: core::ModelTpl<S> — the model every integrator uses, converted to S
/// (model_conversion.hpp) — with the state packed body after body, the switching and clamp
/// functions of its contacts interleaved, and the output rows of the trajectory's columns.
///
/// State, body after body, in the double forms' layout (reference/form_layout.hpp): p_WBr (3),
/// θ_WB (4), v_WBr (3), ω̄ (3) — a pivot without p and v, a prescribed body without all four (its
/// attitude, ω̄ and α̅ are its angle law's at t) — then q_f (n), q̇_f (n); then
/// the contacts' worn depths (h' = the wear rates, docs/wear.md); then the integrals (W_d, W_a,
/// each wear channel's work) when the model dissipates. Equations
/// (docs/design/model.md, quasi-velocity form): ṗ = v, θ̇ = ½ θ ⊗ (0, ω̄), v̇ = a, ω̄̇ = α̅, q̈_f,
/// with (a, α̅, q̈_f) from core::ModelTpl::accelerations_from_wrenches. The model sees θ/|θ|
/// (an orthogonal A whatever drift the integrator leaves in |θ|); θ̇ uses y's θ, so the exact
/// flow conserves |θ|.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "reference/form_layout.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::precision {

template <typename S>
class OdeSystemTpl {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;

  /// Every scene scene::build_model builds (which validates it). Throws std::invalid_argument
  /// for what build_model refuses and for an element or joint kind the conversion to S does not
  /// know (model_conversion.hpp). With ideal joints, output_spacing (s, 0: none given) sets the
  /// Baumgarte rate the double ODE references use (reference::constraint_stabilization_rate).
  OdeSystemTpl(const scene::SceneSpec& spec, core::FlexibleFormulation formulation,
               double output_spacing = 0.0);

  const core::ModelTpl<S>& model() const { return model_; }
  int num_bodies() const { return model_.num_bodies(); }
  /// Where each body's blocks sit in the state (reference/form_layout.hpp).
  const std::vector<reference::BodyBlock>& blocks() const { return blocks_; }
  int mode_count(int i = 0) const { return model_.body(i).mode_count(); }
  /// A body's mass, centre of mass from Br and inertia about Br (body frame), hub and nodes
  /// included, formed in S (the exact solutions' data: exact_high_precision.cpp).
  struct MassProperties {
    S mass;
    Vector3 c_B;
    Matrix3 J_Br_B;
  };
  MassProperties mass_properties(int i) const {
    const core::BodyTpl<S>& b = model_.body(i);
    return {b.mass(), b.p_BrBcm_B(), b.I_Br_B()};
  }
  int state_size() const { return integrals_offset_ + integral_count_; }
  /// The worn depths' first slot in the state and their count.
  int depth_offset() const { return depth_offset_; }
  int depth_count() const { return model_.wear_depth_count(); }
  /// The double model's trajectory::trajectory_columns ("t" first): output_row fills the rest.
  const std::vector<std::string>& columns() const { return columns_; }
  /// Two per switching function of the force elements (a gap support's or contact pair's gap),
  /// in the model's element order: the gap g (it pushes while g < 0; its sign change is an onset
  /// or a release) and the unclamped law's value (NormalLaw::clamp_function).
  int switching_function_count() const { return 2 * model_.switching_function_count(); }
  void switching_functions(S t, const std::vector<S>& y, std::vector<S>& values) const;
  int wear_channel_count() const { return model_.wear_channel_count(); }
  /// The wear channel of a gap support or pair, −1 for an unnamed one.
  int wear_channel_of_pair(int pair) const {
    return model_.switching_channels()[static_cast<std::size_t>(pair)];
  }
  /// Times where a load profile switches, and the end of each spin-up law (φ⁗ jumps there: φ̈ =
  /// (Ω/T)(1 − cos 2πt/T) before, 0 after; extrapolation's high orders need the stop).
  const std::vector<double>& discontinuities() const { return discontinuities_; }

  /// The model's initial state (consistent with its joints in S), the integrals at 0.
  std::vector<S> initial_state() const;

  bool has_constraints() const { return model_.has_constraints(); }
  /// Baumgarte's rate α (1/s) in the accelerations (core::ModelTpl::accelerations_from_wrenches):
  /// a setting of the ODE this system is.
  S constraint_stabilization() const { return stabilization_; }
  void set_constraint_stabilization(S alpha) { stabilization_ = alpha; }
  /// Projects the bodies' state in y onto Φ(q, t) = 0 and J v + Φ_t = 0 (core::ModelTpl::project,
  /// to S's round-off); the integrals are left as they are. Returns the largest relative position
  /// violation before it.
  S project(S t, std::vector<S>& y) const;
  /// The largest relative position violation of the joints at (t, y) (as project's).
  S relative_position_violation(S t, const std::vector<S>& y) const;
  /// The largest relative position and velocity violations of all rows at (t, y) and their rows
  /// (core::ModelTpl::relative_joint_violation).
  core::RelativeJointViolationTpl<S> relative_joint_violation(S t, const std::vector<S>& y) const;
  /// ẏ = f(t, y) on the load branch active at t_segment, with the switching values of the same
  /// evaluation when `switching` is given, the joints on the rows of the system's tracker (as at
  /// the last output_row, the state the integration last accepted). Uses the system's scratch:
  /// one evaluation at a time (the integrators here are sequential).
  void derivative(const std::vector<S>& y, std::vector<S>& dydt, S t, double t_segment,
                  std::vector<S>* switching = nullptr) const;
  /// Kinetic + potential energy at (t, y) (the `energy` column).
  S energy(S t, const std::vector<S>& y) const;
  /// The trajectory_columns row at (t, y) after `t`, a state the integration accepted: the
  /// joints' tracker moves there first (core::ModelTpl::advance_tracker, without the orientation
  /// test: outputs come at any spacing). Per body p_WBo, θ, v_WBo, ω̄, tracked points
  /// (nodes deformed), q_f, q̇_f and a prescribed body's drive torque; per joint its reaction and
  /// violations; the energy, and when the model dissipates W_d, (W_a), E − E(0) + W_d − W_a; per
  /// wear channel Σ F_n, the slip speed of its most loaded support or pair, the wear work and
  /// `impacts` (the caller's onset counts, one per channel; empty: none yet).
  std::vector<S> output_row(S t, const std::vector<S>& y,
                            const std::vector<double>& impacts = {}) const;

 private:
  OdeSystemTpl(const core::Model& built, const std::string& name, double output_spacing);
  /// The bodies' state at (t, y) into state_ (θ normalized; prescribed bodies from their law).
  void unpack(S t, const std::vector<S>& y) const;
  /// state_'s bodies into y (the integrals left as they are).
  void pack(std::vector<S>& y) const;
  /// The gaps and clamps of the scratch interleaved into `values` (g_0, c_0, g_1, c_1, …).
  void interleave_switching(std::vector<S>& values) const;
  core::LoadContextTpl<S> context(S t, double t_segment) const { return {t, t_segment}; }

  core::ModelTpl<S> model_;
  std::vector<std::string> columns_;
  std::vector<double> discontinuities_;
  std::vector<reference::BodyBlock> blocks_ = reference::body_blocks(model_);
  core::StateTpl<S> fixed_;  ///< the initial state: a pivot's position
  int depth_offset_ = 0;     ///< the worn depths' first slot in y
  int integrals_offset_ = 0;
  int integral_count_ = 0;
  bool has_prescribed_ = false;
  S energy0_ = S(0);
  S stabilization_ = S(0);  ///< Baumgarte's rate α (1/s)
  /// The joints' rows in force and their last accepted state: moved at the outputs (output_row),
  /// read by every evaluation.
  mutable core::ConstraintTrackerTpl<S> tracker_;
  mutable core::WorkspaceTpl<S> ws_;
  mutable core::StateTpl<S> state_;
  mutable core::AccelerationsTpl<S> accelerations_;
  mutable std::vector<S> rates_, depth_rates_, gaps_, clamps_;
};

}  // namespace flexref::precision
