#pragma once
/// \file force_element.hpp
/// The interface of everything that applies loads: applied forces and torques, gravity,
/// potentials, contacts, gap supports and bushings. An element adds, for each body it acts on, a
/// force (world) and a torque about the body's reference point Br (world); the model maps
/// these to generalized forces (docs/design/model.md: Qe_R += f, Qe_θ += ũ_P Aᵀ f). On a flexible
/// body a point load given by its position is a load on the rigid part (hub, Φ = 0); loads on
/// the deformable part add the modal force Qe_f += Φ_Pᵀ Aᵀ f (Wrench::Q_f; gravity does this
/// with the invariant S).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/state.hpp"
#include "core/wear_law.hpp"
#include "flexible/modal_data.hpp"

namespace flexref::core {

/// When loads are evaluated: t (in the model's scalar type S), and a time strictly inside the
/// current step or solver interval that selects the active branch of piecewise time laws (see
/// time_profile.hpp); and on which worn geometry: the model passes each element the worn depths
/// of its own points or sectors (StateTpl::wear_depth, ForceElementTpl::wear_depth_count; empty
/// for an element without a wear law, or evaluated outside a model: its initial depths).
template <typename S>
struct LoadContextTpl {
  S t = S(0);
  double t_segment = 0.0;
  std::span<const S> wear_depth = {};
};

using LoadContext = LoadContextTpl<double>;

/// Pose of one body at the evaluation, computed once and shared by all elements; in scalar type S
/// (core::ModelTpl<S>: double for the integrators, extended and quad for the precision
/// references).
template <typename S>
struct BodyKinematicsTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  const BodyStateTpl<S>* state = nullptr;
  Matrix3 R_WB = Matrix3::Identity();  ///< A(θ)
  Vector3 p_BoBr_B = Vector3::Zero();
  /// Flexible bodies: invariants about Br and the modal coordinates the loads see (the state's
  /// under the coupled model; zero under LTE, whose loads act on the undeformed body).
  const flexible::ModalInvariantsTpl<S>* invariants = nullptr;
  const Eigen::Matrix<S, Eigen::Dynamic, 1>* q_f = nullptr;

  /// Arm from Br to a body point given from the frame origin, world frame.
  Vector3 p_BrP_W(const Vector3& p_BoP_B) const { return R_WB * (p_BoP_B - p_BoBr_B); }
  /// World position of a body point given from the frame origin.
  Vector3 p_WP(const Vector3& p_BoP_B) const { return state->p_WBr + p_BrP_W(p_BoP_B); }
  /// World velocity of a body point given from the frame origin: v_Br + ω × p_BrP.
  Vector3 v_WP(const Vector3& p_BoP_B) const {
    return state->v_WBr + R_WB * state->w_WB_B.cross(p_BoP_B - p_BoBr_B);
  }
};

using BodyKinematics = BodyKinematicsTpl<double>;

/// Resultant of the loads on one body: force (world) and torque about Br (world), in scalar type
/// S.
template <typename S>
struct WrenchTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  Vector3 f_W = Vector3::Zero();
  Vector3 tau_Br_W = Vector3::Zero();
  /// Generalized modal force Qe_f (n; empty for a rigid body).
  Eigen::Matrix<S, Eigen::Dynamic, 1> Q_f;
  /// Σ of the magnitudes of the torque contributions about Br that add_force_at summed (N·m):
  /// the scale of the net torque's round-off when contributions cancel (four corner contacts
  /// carrying a block's weight), used by implicit schemes' convergence tests.
  S torque_magnitude = S(0);

  void set_zero() {
    f_W.setZero();
    tau_Br_W.setZero();
    Q_f.setZero();
    torque_magnitude = S(0);
  }
  /// Adds a force applied at a point whose arm from Br is p_BrP_W.
  void add_force_at(const Vector3& force_W, const Vector3& p_BrP_W) {
    using std::sqrt;
    f_W += force_W;
    const Vector3 tau = p_BrP_W.cross(force_W);
    tau_Br_W += tau;
    torque_magnitude += sqrt(tau.squaredNorm());
  }
};

using Wrench = WrenchTpl<double>;

template <typename S>
class BodyTpl;
using Body = BodyTpl<double>;

/// What a wear model consumes from one contact at a state (docs/output.md, "Wear outputs"):
/// the normal force, the slip speed |v_t| of the contact point and the friction power
/// |F_t·v_t| whose time integral is Archard's wear work.
template <typename S>
struct WearSampleTpl {
  S normal_force = S(0);  ///< N, ≥ 0 (summed over a contact's pairs)
  S slip_speed = S(0);    ///< m/s (of the pair carrying the largest normal force)
  S wear_power = S(0);    ///< |F_t·v_t|, W (summed over the pairs)
};

using WearSample = WearSampleTpl<double>;

/// The stiffest mode of a penalty element (a contact's normal law, a joint's spring), as an
/// explicit central-difference scheme sees it: ω = √(k/m_eff) and the largest stable step it
/// allows, 2/ω (a damped mode's (2/ω)(√(1 + ζ²) − ζ)). docs/contact.md and docs/joints.md
/// derive the effective stiffnesses and masses.
struct PenaltyMode {
  /// The element's label and the mode's suffix: "contact 'support' friction", "joint[2]
  /// translational", "spring 'S1'" (core::penalty_modes).
  std::string label;
  std::string kind;         ///< "contact", "joint", "spring"
  int element = -1;         ///< its element's index in Model::elements() (−1: a flexible body)
  double stiffness = 0.0;   ///< effective k (N/m) or k_θ (N·m/rad)
  double inertia = 0.0;     ///< effective mass (kg) or inertia (kg·m²) the mode sees
  double frequency = 0.0;   ///< rad/s
  double step_limit = 0.0;  ///< s
};

/// The interface of a force element in scalar type S (Drake's ForceElement<T>): core::Model
/// evaluates ForceElement = ForceElementTpl<double>; the extended and quad references evaluate
/// the same elements converted to long double and float128 (precision/element_conversion.hpp).
/// Every element's equations are written once, as a class template.
template <typename S>
class ForceElementTpl {
 public:
  using Context = LoadContextTpl<S>;
  using Kinematics = BodyKinematicsTpl<S>;

  virtual ~ForceElementTpl() = default;

  /// Adds this element's loads to the bodies' wrenches. Must not allocate.
  virtual void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                            std::span<WrenchTpl<S>> wrenches) const = 0;
  /// Potential energy of conservative elements (zero for applied loads).
  virtual S potential_energy(const Context& context, std::span<const Kinematics> bodies) const {
    (void)context;
    (void)bodies;
    return S(0);
  }
  /// Power the element dissipates, W (≥ 0: dampers, friction). Its time integral W_d is the
  /// dissipated work of the energy balance E(t) − E(0) + W_d(t) = work of applied loads.
  virtual S dissipated_power(const Context& context, std::span<const Kinematics> bodies) const {
    (void)context;
    (void)bodies;
    return S(0);
  }
  /// Number of switching functions: signed gaps of contacts whose zeros (onset, release) the
  /// references locate with root finding and restart at, so that no step straddles an impact.
  virtual int switching_function_count() const { return 0; }
  /// Writes the switching_function_count() values g_k at this configuration (a gap: positive
  /// when separated, negative when penetrating, m).
  virtual void switching_functions(const Context& context, std::span<const Kinematics> bodies,
                                   std::span<S> g) const {
    (void)context;
    (void)bodies;
    (void)g;
  }
  /// The normal law's unclamped value at each switching function's contact point
  /// (contact::NormalLaw::clamp_function, switching_function_count() values): a penalty force
  /// clamped at F_n ≥ 0 switches inside a contact where it changes sign. The extended and quad
  /// references locate these switches too (precision/switched_integration.hpp). Elements whose
  /// switching functions have no clamp write 1 (no switch).
  virtual void clamp_functions(const Context& context, std::span<const Kinematics> bodies,
                               std::span<S> values) const {
    (void)context;
    (void)bodies;
    std::fill(values.begin(), values.end(), S(1));
  }
  /// What a reference integrating the contacts' work needs at one state, in one pass:
  /// add_wrenches, and at the same state the dissipated power (added to *dissipated), the wear
  /// samples (wear_channel_count() entries) and the switching and clamp functions
  /// (switching_function_count() entries each), each when given (non-null, non-empty). The
  /// default makes the separate calls; a contact overrides it to evaluate each pair once.
  virtual void add_wrenches_and_rates(const Context& context, std::span<const Kinematics> bodies,
                                      std::span<WrenchTpl<S>> wrenches, S* dissipated,
                                      std::span<WearSampleTpl<S>> wear, std::span<S> gaps,
                                      std::span<S> clamps) const {
    add_wrenches(context, bodies, wrenches);
    if (dissipated != nullptr) *dissipated += dissipated_power(context, bodies);
    if (!wear.empty()) wear_samples(context, bodies, wear);
    if (!gaps.empty()) switching_functions(context, bodies, gaps);
    if (!clamps.empty()) clamp_functions(context, bodies, clamps);
  }
  /// Number of wear channels (contacts: one; other elements: none). Each channel's switching
  /// functions are all of the element's (an impact of the channel is an onset of any of them).
  virtual int wear_channel_count() const { return 0; }
  /// The channel's name, the prefix of its CSV columns (C.fn, C.slip_speed, C.wear_work,
  /// C.impacts).
  virtual std::string wear_channel_name() const { return {}; }
  /// The channel's sample at this configuration (wear_channel_count() entries).
  virtual void wear_samples(const Context& context, std::span<const Kinematics> bodies,
                            std::span<WearSampleTpl<S>> samples) const {
    (void)context;
    (void)bodies;
    (void)samples;
  }
  /// Worn depths the element integrates (docs/wear.md): one per contact point or gap-support
  /// sector when it has a wear law, else 0. Its geometry sees them through context.wear_depth.
  virtual int wear_depth_count() const { return 0; }
  /// ḣ of each depth at this configuration, m/s (wear_depth_count() entries).
  virtual void wear_depth_rates(const Context& context, std::span<const Kinematics> bodies,
                                std::span<S> rates) const {
    (void)context;
    (void)bodies;
    (void)rates;
  }
  /// The scar area of depth k, m² (the worn volume is Σ area·h).
  virtual double wear_depth_area(int k) const {
    (void)k;
    return 0.0;
  }
  /// The wear law, or nullptr.
  virtual const WearLaw* wear_law() const { return nullptr; }
  /// True when the element's work is tracked as an integral (applied_work): prescribed loads,
  /// which do work that no potential or dissipation accounts for.
  virtual bool tracks_applied_work() const { return false; }
  /// Power the element's loads put into the bodies, W (tracked elements only).
  virtual S applied_power(const Context& context, std::span<const Kinematics> bodies) const {
    (void)context;
    (void)bodies;
    return S(0);
  }
  /// The time from which every joule the element exchanges with the bodies is in the energy
  /// balance E + W_d − W_a (core/invariants.hpp): its potential energy, its dissipated power or
  /// its tracked applied power. −∞ for potentials, springs, dampers and contacts; the end of a
  /// load pulse; +∞ for a load that keeps doing work. The default, +∞, assumes nothing: an
  /// element that does not say so is never taken to conserve energy.
  virtual double energy_balanced_from() const { return std::numeric_limits<double>::infinity(); }
  /// The time from which the element applies no load at all (the end of a load pulse; +∞:
  /// it acts throughout, the default).
  virtual double loads_end() const { return std::numeric_limits<double>::infinity(); }
  /// Known times where the element's loads jump (both sides must be integrated separately).
  virtual void append_discontinuities(std::vector<double>& times) const { (void)times; }
  /// True when the loads depend on velocities (then schemes use a predicted velocity).
  virtual bool depends_on_velocity() const { return false; }
  /// Largest body index the element refers to (−1 for none); the model checks it.
  virtual int max_body_index() const = 0;
  /// The bodies the element couples, for the sparsity of Jacobians (core/body_coupling.hpp): its
  /// loads on, and the rates of its worn depths from, any listed body may depend on the state of
  /// every listed body (a spring's two ends, a contact's pairs, a one-body element's body). An
  /// element whose load on each body depends on that body's state alone and that integrates no
  /// depths lists none (uniform gravity, a potential of fixed charges). The default lists every
  /// body up to max_body_index(): it assumes the most, so an element that does not say is never
  /// taken to decouple two bodies.
  virtual std::vector<int> coupled_bodies() const {
    std::vector<int> all(static_cast<std::size_t>(std::max(max_body_index() + 1, 0)));
    for (std::size_t b = 0; b < all.size(); ++b) all[b] = static_cast<int>(b);
    return all;
  }
  /// One line saying what the element is, for messages; a body it acts on is named by its
  /// [[body]] table, "body[2]" (core::body_text without the bodies).
  virtual std::string describe() const = 0;
  /// The same line naming the bodies and nodes by their names in `bodies` (the model's; what
  /// `flexref check` prints). By default describe(), for elements that name no body.
  virtual std::string describe_with_names(std::span<const Body> bodies) const {
    (void)bodies;
    return describe();
  }
  /// How messages name the element, as its scene table does: "spring 'S1'" (kind and name),
  /// "joint[2]" (the table, counted from 1, when it has no name); empty for an element built in
  /// code, which core::penalty_modes numbers by kind instead (scene::build_model sets it).
  const std::string& label() const { return label_; }
  void set_label(std::string label) { label_ = std::move(label); }
  /// Appends the element's stiff modes at the bodies' initial state (core/step_limit.hpp),
  /// labelled "" or by a suffix (" translational", " angular"); the model prefixes the
  /// element's label (or kind and number). Elements without stiffness add nothing.
  virtual void append_penalty_modes(std::span<const Body> bodies,
                                    std::vector<PenaltyMode>& modes) const {
    (void)bodies;
    (void)modes;
  }

 private:
  std::string label_;
};

using ForceElement = ForceElementTpl<double>;

}  // namespace flexref::core
