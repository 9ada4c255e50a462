#pragma once
/// \file bushing.hpp
/// Joints as bushings: stiff spring–dampers between two bodies or a body and the ground, as
/// industrial explicit codes model joints (docs/design/scenes.md, "Contacts and joints are penalty
/// elements"; docs/joints.md has the defaults, units and the stiffness/step trade-off).
///
/// Spherical bushing: a point P of body A and a point Q of body B (or a fixed world point)
/// are held together by an isotropic spring–damper. With d = p_WQ − p_WP and the midpoint
/// M = (p_WP + p_WQ)/2,
/// \f[ V = \tfrac12 k\,|d|^2,\qquad u = v_{B}(M) - v_{A}(M),\qquad f = k\,d + c\,u, \f]
/// where v_A(M), v_B(M) are the velocities of the material points of A and B that are at M
/// (u = ḋ + d × (ω_A + ω_B)/2). f acts on A and −f on B, both at M. For the spring part this is
/// the same as acting at P and Q (f ∥ d); for the damper it makes the element objective (a
/// rigid rotation of the whole system is not damped) and its forces collinear, so the sum of
/// moments about any point vanishes. The damper derives from the Rayleigh function
/// ½ c |u|², so its power is −c|u|² ≤ 0.
///
/// Revolute bushing: the spherical part plus an angular spring–damper on the hinge axes
/// a_A (body A) and a_B (body B, or a fixed world axis), unit vectors in world a_A = R_A ā_A:
/// \f[ V_\theta = k_\theta\,(1 - a_A^T a_B),\qquad
///     \tau_A = k_\theta\, a_A \times a_B + c_\theta\, P\,(\omega_B - \omega_A),\qquad
///     \tau_B = -\tau_A,\qquad P = I - \tfrac12 (a_A a_A^T + a_B a_B^T). \f]
/// V_θ = k_θ(1 − cos α) for a misalignment angle α: smooth, a single minimum, a restoring torque
/// k_θ sin α that grows monotonically up to 90° and vanishes only at α = π (whereas
/// ½k_θ|a_A × a_B|² = ½k_θ sin²α would also be stationary at α = 90°, and would hold the
/// flipped hinge a_A = −a_B as firmly as the assembled one). Both have the small-angle stiffness
/// k_θ (N·m/rad). The couples leave rotation about the hinge free; the damper acts on the
/// components of the relative angular velocity perpendicular to the two axes (P is symmetric,
/// between 0 and I, and I − a aᵀ when assembled), power −c_θ ω_relᵀ P ω_rel ≤ 0.
///
/// On a flexible body the attachment point is a point of the rigid part (hub), as for every
/// point load given by its position (force_element.hpp).
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/force_element.hpp"

namespace flexref::contact {

/// Body index meaning "the ground" (fixed world frame) for the second end of a bushing.
constexpr int kGround = -1;

/// One end of a bushing, in scalar type S.
template <typename S>
struct BushingEndTpl {
  int body = kGround;  ///< body index, or kGround (only for the second end)
  /// The attachment point from the body frame origin Bo, body frame (p_BoP_B); for the ground,
  /// the world point p_WQ.
  Eigen::Matrix<S, 3, 1> point = Eigen::Matrix<S, 3, 1>::Zero();
  /// Revolute only: the hinge axis, body frame (ground: world frame); normalized on
  /// construction.
  Eigen::Matrix<S, 3, 1> axis = Eigen::Matrix<S, 3, 1>::UnitZ();
};

using BushingEnd = BushingEndTpl<double>;

/// Stiffness and damping of a bushing (SI units). The defaults are those of docs/joints.md:
/// joint frequencies of 1000 rad/s for m = 1 kg and I = 1e-2 kg·m², stable explicit steps
/// below 2e-3 s; no damping, so that the default joint is conservative.
struct BushingParameters {
  static constexpr double kDefaultStiffness = 1e6;         ///< N/m
  static constexpr double kDefaultAngularStiffness = 1e4;  ///< N·m/rad
  double stiffness = kDefaultStiffness;                    ///< k, N/m
  double damping = 0.0;                                    ///< c, N·s/m
  double angular_stiffness = kDefaultAngularStiffness;     ///< k_θ, N·m/rad (revolute only)
  double angular_damping = 0.0;                            ///< c_θ, N·m·s/rad (revolute only)
};

/// √(stiffness/inertia): the joint's natural frequency, rad/s, for an effective mass (kg,
/// translational) or inertia (kg·m², angular).
double bushing_frequency(double stiffness, double effective_inertia);
/// Largest stable step of an explicit central-difference (leapfrog) scheme on the joint mode,
/// h = (2/ω)(√(1 + ζ²) − ζ) with ζ = damping/(2√(stiffness·inertia)); 2/ω when undamped. +∞
/// for zero stiffness and damping.
double bushing_stable_step(double stiffness, double damping, double effective_inertia);

namespace detail {

/// The checks of the bushings' constructors (their \throws), on the ends in double.
void validate_bushing(const BushingEnd& a, const BushingEnd& b, const BushingParameters& p,
                      bool revolute);
/// "body i point (x, y, z) to ground point (...)" / "... to body j point (...)".
std::string bushing_ends_text(const BushingEnd& a, const BushingEnd& b,
                              std::span<const core::Body> bodies);
/// The joint's translational mode, and for a revolute bushing its angular mode, at the bodies'
/// initial state (append_penalty_modes).
void append_bushing_modes(std::span<const core::Body> bodies, const BushingEnd& a,
                          const BushingEnd& b, const BushingParameters& p, bool revolute,
                          std::vector<core::PenaltyMode>& modes);

}  // namespace detail

/// A point of body A held to a point of body B (or of the ground) by an isotropic
/// spring–damper: the spherical bushing (kRevolute = false). The revolute bushing
/// (kRevolute = true) adds the angular spring–damper that keeps the hinge axes a_A and a_B
/// aligned; rotation about the hinge is free. Generic in the scalar type S
/// (core/force_element.hpp); the definitions and the equations are bushing_impl.hpp's.
template <typename S, bool kRevolute>
class BushingTpl final : public core::ForceElementTpl<S> {
 public:
  using typename core::ForceElementTpl<S>::Context;
  using typename core::ForceElementTpl<S>::Kinematics;

  /// \throws std::invalid_argument when a.body < 0, a.body == b.body, b.body < kGround, a
  /// stiffness or damping is negative or any input is not finite, and for a revolute bushing
  /// when an axis is zero. A spherical bushing sets the angular stiffness and damping to 0.
  BushingTpl(const BushingEndTpl<S>& a, const BushingEndTpl<S>& b,
             const BushingParameters& parameters);
  /// The same bushing in another scalar type (a revolute bushing's axes unit vectors of S).
  template <typename U>
  explicit BushingTpl(const BushingTpl<U, kRevolute>& other);

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<core::WrenchTpl<S>> wrenches) const override;
  S potential_energy(const Context& context, std::span<const Kinematics> bodies) const override;
  S dissipated_power(const Context& context, std::span<const Kinematics> bodies) const override;
  /// Its work is its springs' potential energy and its dampers' dissipated work.
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  /// The ends' motion once for the loads and the dissipated power.
  void add_wrenches_and_rates(const Context& context, std::span<const Kinematics> bodies,
                              std::span<core::WrenchTpl<S>> wrenches, S* dissipated,
                              std::span<core::WearSampleTpl<S>> wear, std::span<S> gaps,
                              std::span<S> clamps) const override;
  bool depends_on_velocity() const override {
    return parameters_.damping > 0.0 || parameters_.angular_damping > 0.0;
  }
  int max_body_index() const override;
  std::vector<int> coupled_bodies() const override;
  std::string describe() const override;
  std::string describe_with_names(std::span<const core::Body> bodies) const override;
  /// "joint" translational, and for a revolute bushing angular (rotations perpendicular to the
  /// hinge): the spring over the smallest effective mass (inertia) of the two ends' added
  /// compliances (contact/compliance.hpp).
  void append_penalty_modes(std::span<const core::Body> bodies,
                            std::vector<core::PenaltyMode>& modes) const override;

  const BushingEndTpl<S>& end_a() const { return a_; }
  const BushingEndTpl<S>& end_b() const { return b_; }
  double translational_stiffness() const { return parameters_.stiffness; }
  double translational_damping() const { return parameters_.damping; }
  /// 0 for a spherical bushing, which has no angular spring.
  double angular_stiffness() const { return parameters_.angular_stiffness; }
  /// 0 for a spherical bushing.
  double angular_damping() const { return parameters_.angular_damping; }
  const BushingParameters& parameters() const { return parameters_; }

 private:
  template <typename, bool>
  friend class BushingTpl;

  BushingEndTpl<S> a_;
  BushingEndTpl<S> b_;
  BushingParameters parameters_;
};

template <typename S>
using SphericalBushingTpl = BushingTpl<S, false>;
template <typename S>
using RevoluteBushingTpl = BushingTpl<S, true>;
using SphericalBushing = SphericalBushingTpl<double>;
using RevoluteBushing = RevoluteBushingTpl<double>;
extern template class BushingTpl<double, false>;
extern template class BushingTpl<double, true>;

}  // namespace flexref::contact
