#pragma once
/// \file contact_impl.hpp
/// The definitions of contact.hpp's class template, included where it is instantiated:
/// contact.cpp (double) and precision/element_conversion.cpp (long double, float128).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "contact/contact.hpp"
#include "contact/contact_point_tpl.hpp"
#include "core/unit_vector_tpl.hpp"

namespace flexref::contact {
namespace detail {

/// The checks of ContactElement's constructor (its \throws).
void validate_contact(const FrictionLaw& friction, double effective_mass);
/// "contact: ... pairs, ..." (ContactElement::describe).
std::string contact_text(const std::vector<ContactPair>& pairs, const NormalLaw& normal,
                         const FrictionLaw& friction, double effective_mass,
                         const std::string& name, double k_eff, double omega, double step);
/// The first pair's body mass (reduced with body_a's for a sphere–sphere pair), shared by the
/// pairs: the contact mode's effective mass when none is given.
double contact_effective_mass(std::span<const core::Body> bodies,
                              const std::vector<ContactPair>& pairs);

/// The pair in S: points and radii exact, the plane normal a unit vector of S.
template <typename S>
ContactPairTpl<S> pair_in(const ContactPair& p) {
  ContactPairTpl<S> q;
  q.kind = p.kind;
  q.body_a = p.body_a;
  q.p_BoCa_B = p.p_BoCa_B.cast<S>();
  q.radius_a = S(p.radius_a);
  q.body_b = p.body_b;
  q.p_BoCb_B = p.p_BoCb_B.cast<S>();
  q.radius_b = S(p.radius_b);
  q.p_WQ = p.p_WQ.cast<S>();
  q.n_W = core::unit_vector_as<S>(p.n_W);
  q.node_a = core::NodeAttachmentTpl<S>(p.node_a);
  q.node_b = core::NodeAttachmentTpl<S>(p.node_b);
  return q;
}

/// The pair's gap, normal and contact point (contact_point_tpl.hpp) at the (deformed) centres,
/// b's sphere worn by `depth` (its radius r_b − depth: the gap grows by depth, the contact point
/// recedes into b along the normal).
template <typename S>
ContactPointTpl<S> pair_point(const ContactPairTpl<S>& pair,
                              std::span<const core::BodyKinematicsTpl<S>> bodies,
                              const S& depth = S(0)) {
  const Eigen::Matrix<S, 3, 1> p_WCb = core::attached_position_W<S>(
      bodies[static_cast<std::size_t>(pair.body_b)], pair.p_BoCb_B, pair.node_b);
  const S radius_b = depth == S(0) ? pair.radius_b : S(pair.radius_b - depth);
  if (pair.kind == ContactPair::Kind::kSpherePlane) {
    return sphere_plane_point_tpl<S>(p_WCb, radius_b, pair.p_WQ, pair.n_W);
  }
  const Eigen::Matrix<S, 3, 1> p_WCa = core::attached_position_W<S>(
      bodies[static_cast<std::size_t>(pair.body_a)], pair.p_BoCa_B, pair.node_a);
  return sphere_sphere_point_tpl<S>(p_WCa, pair.radius_a, p_WCb, radius_b);
}

/// A pair's load: F_n n + F_t on b's sphere at P, its opposite on a's (when a is a body).
template <typename S>
void add_pair_force(const ContactPairTpl<S>& pair, const ContactEvaluationTpl<S>& e,
                    std::span<const core::BodyKinematicsTpl<S>> bodies,
                    std::span<core::WrenchTpl<S>> wrenches) {
  const Eigen::Matrix<S, 3, 1> f_W = e.force_on_b_W();
  const auto b = static_cast<std::size_t>(pair.body_b);
  core::add_attached_force<S>(bodies[b], pair.node_b, f_W, e.point.p_WP, wrenches[b]);
  if (pair.body_a >= 0) {
    const auto a = static_cast<std::size_t>(pair.body_a);
    core::add_attached_force<S>(bodies[a], pair.node_a, -f_W, e.point.p_WP, wrenches[a]);
  }
}

}  // namespace detail

template <typename S>
ContactElementTpl<S>::ContactElementTpl(std::vector<ContactPair> pairs, NormalLaw normal,
                                        FrictionLaw friction, double effective_mass,
                                        std::string name, std::optional<core::WearLaw> wear)
    : pairs_(std::move(pairs)),
      normal_(std::move(normal)),
      friction_(friction),
      effective_mass_(effective_mass),
      name_(std::move(name)),
      wear_(std::move(wear)) {
  detail::validate_contact(friction_, effective_mass_);
  if (wear_) {
    if (name_.empty()) throw std::invalid_argument("a contact with a wear law needs a name");
    core::validate_wear_law(*wear_, false, static_cast<int>(pairs_.size()));
  }
  for (const ContactPair& p : pairs_) pairs_in_s_.push_back(detail::pair_in<S>(p));
}

template <typename S>
template <typename U>
ContactElementTpl<S>::ContactElementTpl(const ContactElementTpl<U>& other)
    : pairs_(other.pairs_),
      normal_(other.normal_),
      friction_(other.friction_),
      effective_mass_(other.effective_mass_),
      name_(other.name_),
      wear_(other.wear_) {
  for (const ContactPair& p : pairs_) pairs_in_s_.push_back(detail::pair_in<S>(p));
}

template <typename S>
S ContactElementTpl<S>::worn_depth(const Context& context, std::size_t pair) const {
  if (!wear_) return S(0);
  if (wear_->geometry_frozen || context.wear_depth.empty()) {
    return wear_->initial_depth.empty() ? S(0) : S(wear_->initial_depth[pair]);
  }
  return context.wear_depth[pair];
}

template <typename S>
void ContactElementTpl<S>::set_load(const ContactPointTpl<S>& point,
                                    ContactEvaluationTpl<S>& e) const {
  if (!wear_) {
    static_cast<PenaltyLoadTpl<S>&>(e) =
        penalty_load_tpl<S>(normal_, friction_, point.gap, point.n_W, e.v_rel_W);
    return;
  }
  // The pair is a flat pin of area A: ḣ = V̇ / A (core/wear_law.hpp).
  static_cast<WornPenaltyLoadTpl<S>&>(e) = worn_penalty_load_tpl<S>(
      normal_, friction_, *wear_, point.gap, point.n_W, S(-point.n_W.dot(e.v_rel_W)), e.v_rel_W,
      S(1), S(1) / S(wear_->area));
}

template <typename S>
typename ContactElementTpl<S>::Vector3 ContactElementTpl<S>::relative_velocity(
    const ContactPairTpl<S>& pair, std::span<const Kinematics> bodies, const Vector3& p_WP) const {
  // v_Br + ω × (P − p_WBr) (+ A Φ_k q̇_f at a node) of b's sphere, minus a's.
  Vector3 v = core::attached_velocity_W<S>(bodies[static_cast<std::size_t>(pair.body_b)], p_WP,
                                           pair.node_b);
  if (pair.body_a >= 0) {
    v -= core::attached_velocity_W<S>(bodies[static_cast<std::size_t>(pair.body_a)], p_WP,
                                      pair.node_a);
  }
  return v;
}

template <typename S>
ContactEvaluationTpl<S> ContactElementTpl<S>::evaluate(int pair_index,
                                                       std::span<const Kinematics> bodies) const {
  return evaluate(Context{}, pair_index, bodies);
}

template <typename S>
ContactEvaluationTpl<S> ContactElementTpl<S>::evaluate(const Context& context, int pair_index,
                                                       std::span<const Kinematics> bodies) const {
  const auto i = static_cast<std::size_t>(pair_index);
  const ContactPairTpl<S>& pair = pairs_in_s_[i];
  ContactEvaluationTpl<S> e;
  e.point = detail::pair_point<S>(pair, bodies, worn_depth(context, i));
  if (e.point.gap >= S(0)) return e;  // separated (or touching): no force
  e.v_rel_W = relative_velocity(pair, bodies, e.point.p_WP);
  set_load(e.point, e);
  return e;
}

template <typename S>
void ContactElementTpl<S>::add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                                        std::span<core::WrenchTpl<S>> wrenches) const {
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    const ContactEvaluationTpl<S> e = evaluate(context, static_cast<int>(i), bodies);
    if (e.normal.total == S(0)) continue;
    const ContactPairTpl<S>& pair = pairs_in_s_[i];
    detail::add_pair_force<S>(pair, e, bodies, wrenches);
  }
}

template <typename S>
void ContactElementTpl<S>::add_wrenches_and_rates(const Context& context,
                                                  std::span<const Kinematics> bodies,
                                                  std::span<core::WrenchTpl<S>> wrenches,
                                                  S* dissipated,
                                                  std::span<core::WearSampleTpl<S>> wear,
                                                  std::span<S> gaps, std::span<S> clamps) const {
  using std::abs;
  using std::sqrt;
  core::WearSampleTpl<S> w{};
  S largest(0);
  S power(0);  // dissipated_power's sum over the pairs, added once
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    // evaluate()'s load, with v_rel also while separated (the clamp function).
    const ContactPairTpl<S>& pair = pairs_in_s_[i];
    ContactEvaluationTpl<S> e;
    e.point = detail::pair_point<S>(pair, bodies, worn_depth(context, i));
    e.v_rel_W = relative_velocity(pair, bodies, e.point.p_WP);
    set_load(e.point, e);
    if (!gaps.empty()) gaps[i] = e.point.gap;
    if (!clamps.empty()) {
      clamps[i] = normal_.clamp_function(S(-e.point.gap), S(-e.point.n_W.dot(e.v_rel_W)));
    }
    power += e.dissipated_power();
    if (e.normal.total == S(0)) continue;
    // ∂V_law(δ)/∂h ḣ with δ = −(g + h): −F_e ḣ leaves the spring.
    if (wear_) power += e.normal.elastic * e.recession;
    // wear_samples' Σ F_n, Σ |F_t·v_t| and the slip speed of the most loaded pair.
    w.normal_force += e.normal.total;
    w.wear_power += abs(e.f_friction_W.dot(e.v_t_W));
    if (e.normal.total > largest) {
      largest = e.normal.total;
      w.slip_speed = sqrt(e.v_t_W.squaredNorm());
    }
    detail::add_pair_force<S>(pair, e, bodies, wrenches);
  }
  if (dissipated != nullptr) *dissipated += power;
  if (!wear.empty()) wear[0] = w;
}

template <typename S>
S ContactElementTpl<S>::potential_energy(const Context& context,
                                         std::span<const Kinematics> bodies) const {
  S v(0);
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    v += normal_.potential_in(
        S(-detail::pair_point<S>(pairs_in_s_[i], bodies, worn_depth(context, i)).gap));
  }
  return v;
}

template <typename S>
S ContactElementTpl<S>::dissipated_power(const Context& context,
                                         std::span<const Kinematics> bodies) const {
  S p(0);
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    const ContactEvaluationTpl<S> e = evaluate(context, static_cast<int>(i), bodies);
    p += e.dissipated_power();
    if (wear_) p += e.normal.elastic * e.recession;
  }
  return p;
}

template <typename S>
void ContactElementTpl<S>::wear_depth_rates(const Context& context,
                                            std::span<const Kinematics> bodies,
                                            std::span<S> rates) const {
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    rates[i] = evaluate(context, static_cast<int>(i), bodies).volume_rate / S(wear_->area);
  }
}

template <typename S>
void ContactElementTpl<S>::wear_samples(const Context& context, std::span<const Kinematics> bodies,
                                        std::span<core::WearSampleTpl<S>> samples) const {
  using std::abs;
  using std::sqrt;
  core::WearSampleTpl<S>& w = samples[0];
  w = core::WearSampleTpl<S>{};
  S largest(0);
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    const ContactEvaluationTpl<S> e = evaluate(context, static_cast<int>(i), bodies);
    if (e.normal.total == S(0)) continue;
    w.normal_force += e.normal.total;
    w.wear_power += abs(e.f_friction_W.dot(e.v_t_W));  // |F_t·v_t|
    if (e.normal.total > largest) {
      largest = e.normal.total;
      w.slip_speed = sqrt(e.v_t_W.squaredNorm());
    }
  }
}

template <typename S>
void ContactElementTpl<S>::switching_functions(const Context& context,
                                               std::span<const Kinematics> bodies,
                                               std::span<S> g) const {
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    g[i] = detail::pair_point<S>(pairs_in_s_[i], bodies, worn_depth(context, i)).gap;
  }
}

template <typename S>
void ContactElementTpl<S>::clamp_functions(const Context& context,
                                           std::span<const Kinematics> bodies,
                                           std::span<S> values) const {
  for (std::size_t i = 0; i < pairs_in_s_.size(); ++i) {
    const ContactPairTpl<S>& pair = pairs_in_s_[i];
    const ContactPointTpl<S> p = detail::pair_point<S>(pair, bodies, worn_depth(context, i));
    const Vector3 v_rel = relative_velocity(pair, bodies, p.p_WP);
    values[i] = normal_.clamp_function(S(-p.gap), S(-p.n_W.dot(v_rel)));
  }
}

template <typename S>
int ContactElementTpl<S>::max_body_index() const {
  int m = -1;
  for (const ContactPair& p : pairs_) m = std::max({m, p.body_a, p.body_b});
  return m;
}

template <typename S>
std::vector<int> ContactElementTpl<S>::coupled_bodies() const {
  std::vector<int> bodies;
  for (const ContactPair& p : pairs_) {
    for (const int b : {p.body_a, p.body_b}) {
      if (b >= 0 && std::find(bodies.begin(), bodies.end(), b) == bodies.end()) bodies.push_back(b);
    }
  }
  return bodies;
}

template <typename S>
double ContactElementTpl<S>::effective_stiffness(double effective_mass) const {
  if (normal_.kind() == NormalLaw::Kind::kLinear) return normal_.stiffness();
  return normal_.linearized_stiffness(
      normal_.impact_penetration(effective_mass, normal_.reference_speed()));
}

template <typename S>
double ContactElementTpl<S>::frequency(double effective_mass) const {
  return std::sqrt(effective_stiffness(effective_mass) / effective_mass);
}

template <typename S>
double ContactElementTpl<S>::explicit_step_limit(double effective_mass) const {
  return 2.0 / frequency(effective_mass);
}

template <typename S>
void ContactElementTpl<S>::append_penalty_modes(std::span<const core::Body> bodies,
                                                std::vector<core::PenaltyMode>& modes) const {
  const double m_eff =
      effective_mass_ > 0.0 ? effective_mass_ : detail::contact_effective_mass(bodies, pairs_);
  core::PenaltyMode mode;
  mode.kind = "contact";
  mode.inertia = m_eff;
  mode.stiffness = effective_stiffness(m_eff);
  mode.frequency = frequency(m_eff);
  mode.step_limit = explicit_step_limit(m_eff);
  modes.push_back(mode);
}

template <typename S>
std::string ContactElementTpl<S>::describe() const {
  const bool known = effective_mass_ > 0.0;
  const std::string text = detail::contact_text(pairs_, normal_, friction_, effective_mass_, name_,
                                                known ? effective_stiffness(effective_mass_) : 0.0,
                                                known ? frequency(effective_mass_) : 0.0,
                                                known ? explicit_step_limit(effective_mass_) : 0.0);
  return wear_ ? text + "; " + wear_->describe() : text;
}

}  // namespace flexref::contact
