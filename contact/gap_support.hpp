#pragma once
/// \file gap_support.hpp
/// A support with clearance around a fixed axis (docs/contact.md, "Gap support"): the tube in
/// its support plate. A body point N — a node of a flexible body (core/node_attachment.hpp) or
/// a point of a rigid body — moves freely while it stays within the clearance c of the support
/// axis (point S, unit direction a, world frame) and is pushed back with the contact laws of
/// contact_laws.hpp when it leaves it:
///   circular  d = (I − a aᵀ)(p_WN − p_WS),  g = c − |d|,           n = −d/|d|
///   planar    s = m·(p_WN − p_WS),          g = c − |s|,           n = −sign(s) m
///             (m ⊥ a: the support acts in one transverse direction only, two planes at ±c)
/// with the penetration δ = −g, δ̇ = −n·v_N (v_N the velocity of the deformed point, the support
/// is fixed), the normal force F_n n and the friction −μ F_n tanh(|v_t|/v_reg) v_t/|v_t| on the
/// slip velocity v_t = v_N − (n·v_N) n (axial and circumferential sliding) at the point N.
/// The normal force is −∇V of V = V_law(δ): δ = |d| − c has gradient d/|d| = −n.
///
/// Wear (docs/wear.md, circular supports): with a wear law the hole's circumference is cut into
/// S sectors around the axis, each with a worn depth h_j (states of the model,
/// LoadContextTpl::wear_depth), and the clearance at the angle φ of d is c + h(φ), h the
/// periodic C¹ profile through the sector depths (worn_profile_tpl.hpp). φ is measured about a
/// from e1, the first world axis of (x, y, z) least aligned with a, projected normal to a, toward
/// e2 = a × e1. Then
///   δ = |d| − c − h(φ),   ∇δ = e_r − (h'(φ)/|d|) e_φ   (e_r = d/|d|, e_φ = a × e_r),
///   load on N: −F_n ∇δ (F_n = NormalLaw(δ, δ̇), δ̇ = ∇δ·v_N), n = −∇δ/|∇δ|,
/// so the normal force is still exactly −∇V of V = V_law(δ) on the worn hole (its magnitude
/// F_n |∇δ|; the tangential part pushes the point along the scar's slope); friction acts on the
/// slip v_t = v_N − (n·v_N) n with that magnitude. A contact at φ wears the two sectors whose
/// centres bracket it (hat weights), ḣ_j = w_j V̇ / A_s with A_s = (2π r/S) w, so the hole
/// recedes at the point at ḣ(φ) = Σ b_j(φ) ḣ_j (b_j the profile's weights), and the law's
/// damping sees δ̇ = ∇δ·v_N − ḣ(φ) (penalty_load_tpl.hpp, worn_penalty_load_tpl). The spring's
/// energy then changes by −F_e ḣ(φ): that power is in dissipated_power, so the energy balance
/// holds on a wearing hole.
/// Generic in the scalar type S (core/force_element.hpp); the definitions are
/// gap_support_impl.hpp's.
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "contact/contact_laws.hpp"
#include "contact/penalty_load_tpl.hpp"
#include "contact/worn_profile_tpl.hpp"
#include "core/force_element.hpp"
#include "core/node_attachment.hpp"

namespace flexref::contact {

struct GapSupportGeometry {
  enum class Kind { kCircular, kPlanar };
  Kind kind = Kind::kCircular;
  Eigen::Vector3d p_WS = Eigen::Vector3d::Zero();  ///< a point of the support axis, m
  Eigen::Vector3d a_W = Eigen::Vector3d::UnitX();  ///< unit support axis
  Eigen::Vector3d m_W = Eigen::Vector3d::UnitZ();  ///< planar: unit normal of the planes, ⊥ a
  double clearance = 1e-3;                         ///< c, m (> 0)
};

/// The support's data in S (GapSupportGeometry's, unit axis and normal as it normalized them).
template <typename S>
struct GapGeometryTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  bool circular = true;
  Vector3 p_WS = Vector3::Zero();
  Vector3 a_W = Vector3::UnitX();
  Vector3 m_W = Vector3::UnitZ();
  S clearance = S(0);
};

/// The support, generic in the scalar type S (core/force_element.hpp); the definitions are
/// gap_support_impl.hpp's (the geometry gap_point_tpl, the load penalty_load_tpl.hpp's).
template <typename S>
class GapSupportTpl final : public core::ForceElementTpl<S> {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using typename core::ForceElementTpl<S>::Context;
  using typename core::ForceElementTpl<S>::Kinematics;

  /// Gap, normal and contact point of the support at a configuration.
  struct Point {
    S gap = S(0);
    Vector3 n_W = Vector3::UnitZ();  ///< on the body, toward the axis
    Vector3 p_WN = Vector3::Zero();  ///< the (deformed) point
  };

  /// The point p_BoN_B of `body` (a node's undeformed position when `node` deforms). Throws
  /// std::invalid_argument for a non-unit or dependent axis/normal or a clearance ≤ 0.
  /// effective_mass (kg, 0: the body's mass) only sets the penalty mode of the step limit.
  /// A wear law (a circular support only; core::validate_wear_law, one depth per sector) needs a
  /// name (std::invalid_argument).
  GapSupportTpl(int body, const Vector3& p_BoN_B, core::NodeAttachmentTpl<S> node,
                GapSupportGeometry geometry, NormalLaw normal, FrictionLaw friction,
                double effective_mass = 0.0, std::string name = {},
                std::optional<core::WearLaw> wear = std::nullopt);
  /// The same support in another scalar type (its axis and normal unit vectors of S).
  template <typename U>
  explicit GapSupportTpl(const GapSupportTpl<U>& other);

  Point gap_point(std::span<const Kinematics> bodies) const;

  /// Everything the support applies at a state: penetration rate, slip velocity, forces.
  /// δ̇, v_t, F_n, F_t and the dissipated power are penalty_load_tpl's (penalty_load_tpl.hpp);
  /// on a worn hole δ̇ = ∇δ·v_N and the normal force is F_n |∇δ| along n.
  struct Evaluation : WornPenaltyLoadTpl<S> {
    Point point;
    S gradient_norm = S(1);            ///< |∇δ| (1 on an unworn hole)
    WornProfileWeightsTpl<S> profile;  ///< the worn profile's weights at the point's angle
    /// The normal force's magnitude, N.
    S normal_force() const { return this->normal.total * gradient_norm; }
    Vector3 force_W() const { return normal_force() * point.n_W + this->f_friction_W; }
  };
  /// On the support's initial geometry, or on the worn geometry of a context.
  Evaluation evaluate(std::span<const Kinematics> bodies) const;
  Evaluation evaluate(const Context& context, std::span<const Kinematics> bodies) const;

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<core::WrenchTpl<S>> wrenches) const override;
  S potential_energy(const Context& context, std::span<const Kinematics> bodies) const override;
  S dissipated_power(const Context& context, std::span<const Kinematics> bodies) const override;
  /// Its work is the penalty spring's potential energy and the work its damping and friction
  /// dissipate.
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  int switching_function_count() const override { return 1; }
  void switching_functions(const Context& context, std::span<const Kinematics> bodies,
                           std::span<S> g) const override;
  /// The normal law's unclamped value NormalLaw::clamp_function(δ, δ̇) at the point, with
  /// δ̇ = −n·v_N also while separated.
  void clamp_functions(const Context& context, std::span<const Kinematics> bodies,
                       std::span<S> values) const override;
  /// One evaluation of the point for all of them.
  void add_wrenches_and_rates(const Context& context, std::span<const Kinematics> bodies,
                              std::span<core::WrenchTpl<S>> wrenches, S* dissipated,
                              std::span<core::WearSampleTpl<S>> wear, std::span<S> gaps,
                              std::span<S> clamps) const override;
  bool depends_on_velocity() const override { return true; }
  int wear_channel_count() const override { return name_.empty() ? 0 : 1; }
  std::string wear_channel_name() const override { return name_; }
  void wear_samples(const Context& context, std::span<const Kinematics> bodies,
                    std::span<core::WearSampleTpl<S>> samples) const override;
  int wear_depth_count() const override { return wear_ ? wear_->sectors : 0; }
  /// ḣ_j of every sector (the two bracketing the contact's angle, 0 elsewhere).
  void wear_depth_rates(const Context& context, std::span<const Kinematics> bodies,
                        std::span<S> rates) const override;
  double wear_depth_area(int) const override { return wear_ ? wear_->sector_area() : 0.0; }
  const core::WearLaw* wear_law() const override { return wear_ ? &*wear_ : nullptr; }
  /// The sector angle φ of a point (rad, in (−π, π]) and the basis it is measured in.
  S sector_angle(const Vector3& p_WN) const;
  int max_body_index() const override { return body_; }
  std::vector<int> coupled_bodies() const override { return {body_}; }
  std::string describe() const override;
  std::string describe_with_names(std::span<const core::Body> bodies) const override;
  void append_penalty_modes(std::span<const core::Body> bodies,
                            std::vector<core::PenaltyMode>& modes) const override;

  /// The geometry as given (double; its axis and normal normalized in double).
  const GapSupportGeometry& geometry() const { return geometry_; }
  int body() const { return body_; }
  const NormalLaw& normal_law() const { return normal_; }
  const FrictionLaw& friction_law() const { return friction_; }

 private:
  template <typename>
  friend class GapSupportTpl;

  int body_;
  Vector3 p_BoN_B_;
  core::NodeAttachmentTpl<S> node_;
  GapSupportGeometry geometry_;
  GapGeometryTpl<S> geometry_in_s_;  ///< geometry_ in S
  NormalLaw normal_;
  FrictionLaw friction_;
  double effective_mass_;
  std::string name_;
  std::optional<core::WearLaw> wear_;
  Vector3 e1_W_ = Vector3::UnitY();  ///< the sectors' angle origin, ⊥ a
  Vector3 e2_W_ = Vector3::UnitZ();  ///< a × e1
  std::vector<S> initial_depth_;     ///< the law's initial depths in S (zeros when none)

  /// The depths the geometry sees: the context's, or the initial ones (frozen geometry, none
  /// given).
  std::span<const S> worn_depths(const Context& context) const;
  /// The load on the worn hole (wear law): the point, and with `loaded_only` nothing more while
  /// separated.
  Evaluation evaluate_worn(const Context& context, std::span<const Kinematics> bodies,
                           bool loaded_only) const;
  void set_sector_basis();
};

using GapSupport = GapSupportTpl<double>;
using GapPoint = GapSupport::Point;
extern template class GapSupportTpl<double>;

}  // namespace flexref::contact
