#pragma once
/// \file contact.hpp
/// Penalty contacts between body-fixed spheres and ground planes or other spheres
/// (docs/contact.md). Each pair has a signed gap g (> 0 separated, < 0 penetrating, m), a unit
/// normal n_W from side a (the ground plane or sphere a) to side b (the sphere that the normal
/// force pushes away), and a contact point P:
///   sphere–plane   g = n·(p_WC − p_WQ) − r,            P = C − r n
///   sphere–sphere  g = |C_b − C_a| − r_a − r_b,       n = (C_b − C_a)/|C_b − C_a|,
///                  P = C_a + (r_a + g/2) n            (midway between the two surfaces)
/// A point contact is a sphere of radius 0. With the penetration δ = −g and its rate
/// δ̇ = −n·v_rel (v_rel: velocity of b's material point at P minus a's), the normal law gives
/// F_n ≥ 0 (contact_laws.hpp) and friction F_t = −μ F_n tanh(|v_t|/v_reg) v_t/|v_t| on the
/// tangential part v_t of v_rel. Body b receives F_n n + F_t at P, body a (if any) the
/// opposite. The normal force lies on the line through the sphere centres, so its torque is
/// the same at any point of that line and the force is exactly −∇V of V = Σ V_law(δ).
/// A sphere is attached to a body's rigid part (a flexible body's hub: Φ = 0 at the sphere)
/// or to a node of a flexible body (core/node_attachment.hpp): its centre is then the deformed
/// node x_k + Φ_k q_f, the velocity of its material point at P gains A Φ_k q̇_f, and the force
/// adds Φ_kᵀ Aᵀ f to the modal rows. A named contact has a wear channel (docs/output.md).
///
/// Wear (docs/wear.md): with a wear law, each pair i has a worn depth h_i (a state of the model,
/// LoadContextTpl::wear_depth) by which b's sphere is worn: its radius is r_b − h_i, so the gap
/// grows by h_i and the contact point recedes along the normal into b. Each pair is a flat pin
/// of area A: ḣ_i = V̇_i / A with V̇_i the law's volume rate (core/wear_law.hpp) at the pair's
/// F_n, |v_t| and |F_t·v_t|, and the law's damping sees the penetration rate of the worn
/// surfaces, δ̇ = −n·v_rel − ḣ_i (penalty_load_tpl.hpp, worn_penalty_load_tpl): a pin that wears
/// at a steady rate while its body sinks with it is not damped. The spring's energy V_law(δ)
/// with δ = −(g + h_i) changes by −F_e ḣ_i when the depth grows: that power, F_e ḣ_i, is in
/// dissipated_power, so that the energy balance E + W_d − W_a still accounts for every joule.
/// The element is generic in the scalar type S (core/force_element.hpp).
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "contact/contact_laws.hpp"
#include "contact/contact_point_tpl.hpp"
#include "contact/penalty_load_tpl.hpp"
#include "core/force_element.hpp"
#include "core/node_attachment.hpp"

namespace flexref::contact {

/// One contact pair. Build it with the named constructors.
struct ContactPair {
  enum class Kind { kSpherePlane, kSphereSphere };
  Kind kind = Kind::kSpherePlane;
  int body_a = -1;  ///< sphere a's body; −1 for the ground plane
  Eigen::Vector3d p_BoCa_B = Eigen::Vector3d::Zero();
  double radius_a = 0.0;
  int body_b = 0;  ///< the sphere body pushed along +n
  Eigen::Vector3d p_BoCb_B = Eigen::Vector3d::Zero();
  double radius_b = 0.0;
  Eigen::Vector3d p_WQ = Eigen::Vector3d::Zero();  ///< a point of the plane (sphere–plane)
  Eigen::Vector3d n_W = Eigen::Vector3d::UnitZ();  ///< unit plane normal, toward the free side
  core::NodeAttachment node_a;  ///< sphere a at a node (p_BoCa_B is then the node's x_k)
  core::NodeAttachment node_b;  ///< sphere b at a node

  /// Sphere of radius r ≥ 0 at body point C (from Bo, body frame) on the ground plane through
  /// Q with normal n (normalized here; must be nonzero).
  static ContactPair sphere_plane(int body, const Eigen::Vector3d& p_BoC_B, double radius,
                                  const Eigen::Vector3d& p_WQ, const Eigen::Vector3d& n_W);
  /// A body point on the ground plane: a sphere of radius 0.
  static ContactPair point_plane(int body, const Eigen::Vector3d& p_BoP_B,
                                 const Eigen::Vector3d& p_WQ, const Eigen::Vector3d& n_W);
  /// Sphere a on body a against sphere b on another body b.
  static ContactPair sphere_sphere(int body_a, const Eigen::Vector3d& p_BoCa_B, double radius_a,
                                   int body_b, const Eigen::Vector3d& p_BoCb_B, double radius_b);
};

/// Gap, normal and contact point of a pair at a configuration.
using ContactPoint = ContactPointTpl<double>;  ///< gap, unit normal a → b, contact point P

/// Geometry of one pair. Coincident sphere centres (no direction) give n = e_z and
/// g = −r_a − r_b.
ContactPoint contact_point(const ContactPair& pair, std::span<const core::BodyKinematics> bodies);

/// Everything one pair contributes at a state.
/// δ̇, v_t, F_n, F_t and the dissipated power F_nc δ̇ − F_t·v_t ≥ 0 are penalty_load_tpl's.
template <typename S>
struct ContactEvaluationTpl : WornPenaltyLoadTpl<S> {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  ContactPointTpl<S> point;
  Vector3 v_rel_W = Vector3::Zero();  ///< b's point at P minus a's, m/s
  /// Total force on b (on a: its opposite), N.
  Vector3 force_on_b_W() const { return this->normal.total * point.n_W + this->f_friction_W; }
};

using ContactEvaluation = ContactEvaluationTpl<double>;

/// A pair's data in S: ContactPair's points and radii exact, its plane normal a unit vector of S
/// (core/unit_vector_tpl.hpp), its node attachments' Φ_k exact.
template <typename S>
struct ContactPairTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  ContactPair::Kind kind = ContactPair::Kind::kSpherePlane;
  int body_a = -1;
  Vector3 p_BoCa_B = Vector3::Zero();
  S radius_a = S(0);
  int body_b = 0;
  Vector3 p_BoCb_B = Vector3::Zero();
  S radius_b = S(0);
  Vector3 p_WQ = Vector3::Zero();
  Vector3 n_W = Vector3::UnitZ();
  core::NodeAttachmentTpl<S> node_a;
  core::NodeAttachmentTpl<S> node_b;
};

/// A set of contact pairs sharing one normal law and one friction law. Generic in the scalar
/// type S (core/force_element.hpp); the definitions are contact_impl.hpp's. The pairs are given
/// in double (ContactPair), as the scene has them, and evaluated in S.
template <typename S>
class ContactElementTpl final : public core::ForceElementTpl<S> {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using typename core::ForceElementTpl<S>::Context;
  using typename core::ForceElementTpl<S>::Kinematics;

  /// effective_mass (kg, > 0 or 0 for unknown) is used only for describe()'s frequency and
  /// explicit step limit.
  /// A non-empty name gives the element a wear channel with that name.
  /// A wear law (core::validate_wear_law; one depth per pair) needs a name (std::invalid_argument).
  ContactElementTpl(std::vector<ContactPair> pairs, NormalLaw normal, FrictionLaw friction,
                    double effective_mass = 0.0, std::string name = {},
                    std::optional<core::WearLaw> wear = std::nullopt);
  /// The same contacts in another scalar type.
  template <typename U>
  explicit ContactElementTpl(const ContactElementTpl<U>& other);

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<core::WrenchTpl<S>> wrenches) const override;
  /// Elastic energy of the penalty springs, Σ V_law(δ).
  S potential_energy(const Context& context, std::span<const Kinematics> bodies) const override;
  S dissipated_power(const Context& context, std::span<const Kinematics> bodies) const override;
  /// Its work is the penalty springs' potential energy and the work its damping and friction
  /// dissipate.
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  int switching_function_count() const override { return static_cast<int>(pairs_.size()); }
  /// The gap of each pair, in order.
  void switching_functions(const Context& context, std::span<const Kinematics> bodies,
                           std::span<S> g) const override;
  /// NormalLaw::clamp_function(δ, δ̇) of each pair, in order, δ̇ = −n·v_rel also while separated.
  void clamp_functions(const Context& context, std::span<const Kinematics> bodies,
                       std::span<S> values) const override;
  /// One evaluation of each pair for all of them.
  void add_wrenches_and_rates(const Context& context, std::span<const Kinematics> bodies,
                              std::span<core::WrenchTpl<S>> wrenches, S* dissipated,
                              std::span<core::WearSampleTpl<S>> wear, std::span<S> gaps,
                              std::span<S> clamps) const override;
  bool depends_on_velocity() const override { return true; }
  int wear_channel_count() const override { return name_.empty() ? 0 : 1; }
  std::string wear_channel_name() const override { return name_; }
  /// Σ F_n, the slip speed of the pair carrying the largest normal force, Σ |F_t·v_t|.
  void wear_samples(const Context& context, std::span<const Kinematics> bodies,
                    std::span<core::WearSampleTpl<S>> samples) const override;
  int max_body_index() const override;
  /// The bodies of all its pairs (the ground left out).
  std::vector<int> coupled_bodies() const override;
  std::string describe() const override;
  /// One mode "contact": the effective stiffness at the effective mass (the constructor's, or
  /// when 0 the first pair's body mass shared by the pairs, reduced with body_b's for
  /// sphere-sphere pairs).
  void append_penalty_modes(std::span<const core::Body> bodies,
                            std::vector<core::PenaltyMode>& modes) const override;

  /// One pair's contribution at a state, on the contact's initial geometry (its law's initial
  /// depths) or on the worn geometry of a context.
  ContactEvaluationTpl<S> evaluate(int pair, std::span<const Kinematics> bodies) const;
  ContactEvaluationTpl<S> evaluate(const Context& context, int pair,
                                   std::span<const Kinematics> bodies) const;

  int wear_depth_count() const override { return wear_ ? static_cast<int>(pairs_.size()) : 0; }
  /// ḣ_i = V̇_i / A of every pair (0 while separated).
  void wear_depth_rates(const Context& context, std::span<const Kinematics> bodies,
                        std::span<S> rates) const override;
  double wear_depth_area(int) const override { return wear_ ? wear_->area : 0.0; }
  const core::WearLaw* wear_law() const override { return wear_ ? &*wear_ : nullptr; }

  /// Stiffness the explicit step sees with a mass m_eff (N/m): k for the linear law; for
  /// Hunt–Crossley the linearized n k δⁿ⁻¹ at the largest penetration of an undamped impact
  /// at v_ref, δ_max = ((n + 1) m v_ref²/(2k))^{1/(n+1)}.
  double effective_stiffness(double effective_mass) const;
  /// √(k_eff/m_eff), rad/s.
  double frequency(double effective_mass) const;
  /// Central-difference stability limit 2/ω of the undamped contact, s (damping lowers it by
  /// √(1 + ζ²) − ζ; docs/contact.md).
  double explicit_step_limit(double effective_mass) const;

  const std::vector<ContactPair>& pairs() const { return pairs_; }
  const NormalLaw& normal_law() const { return normal_; }
  const FrictionLaw& friction_law() const { return friction_; }

 private:
  template <typename>
  friend class ContactElementTpl;

  std::vector<ContactPair> pairs_;
  std::vector<ContactPairTpl<S>> pairs_in_s_;  ///< pairs_ in S
  NormalLaw normal_;
  FrictionLaw friction_;
  double effective_mass_;
  std::string name_;
  std::optional<core::WearLaw> wear_;

  /// The worn depth pair i's geometry sees: the context's (its state), or the law's initial
  /// depth when the geometry is frozen or no depths are given; 0 without a wear law.
  S worn_depth(const Context& context, std::size_t pair) const;
  /// Pair i's load at its point and relative velocity: penalty_load_tpl's, or with a wear law
  /// worn_penalty_load_tpl's.
  void set_load(const ContactPointTpl<S>& point, ContactEvaluationTpl<S>& e) const;

  /// Relative velocity of b's material point at P minus a's.
  Vector3 relative_velocity(const ContactPairTpl<S>& pair, std::span<const Kinematics> bodies,
                            const Vector3& p_WP) const;
};

using ContactElement = ContactElementTpl<double>;
extern template class ContactElementTpl<double>;

}  // namespace flexref::contact
