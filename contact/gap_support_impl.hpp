#pragma once
/// \file gap_support_impl.hpp
/// The definitions of gap_support.hpp's class template, included where it is instantiated:
/// gap_support.cpp (double) and precision/element_conversion.cpp (long double, float128).
#include <array>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "contact/gap_support.hpp"
#include "core/element_text.hpp"
#include "core/unit_vector_tpl.hpp"

namespace flexref::contact {

/// Gap and normal at the (deformed) point p_WN.
template <typename S>
struct GapPointTpl {
  S gap = S(0);
  Eigen::Matrix<S, 3, 1> n_W = Eigen::Matrix<S, 3, 1>::UnitZ();  ///< on the body, toward the axis
};

/// The gap and normal of gap_support.hpp's circular or planar support at p_WN.
template <typename S>
GapPointTpl<S> gap_point_tpl(const GapGeometryTpl<S>& geometry,
                             const Eigen::Matrix<S, 3, 1>& p_WN) {
  using std::abs;
  using std::sqrt;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  GapPointTpl<S> c;
  const Vector3 r = p_WN - geometry.p_WS;
  if (geometry.circular) {
    const Vector3 d = r - geometry.a_W.dot(r) * geometry.a_W;  // (I − a aᵀ) r
    const S distance = sqrt(d.squaredNorm());
    c.gap = geometry.clearance - distance;
    // On the axis there is no direction, and no force (g = c > 0).
    c.n_W = distance > S(0) ? Vector3(-d / distance) : geometry.m_W;
  } else {
    const S s = geometry.m_W.dot(r);
    c.gap = geometry.clearance - abs(s);
    c.n_W = s >= S(0) ? Vector3(-geometry.m_W) : geometry.m_W;
  }
  return c;
}

namespace detail {

/// The checks of GapSupport's constructor (its \throws); normalizes the axis, and the planes'
/// normal projected on the plane normal to the axis, in double.
void validate_gap_support(int body, const Eigen::Vector3d& p_BoN_B, GapSupportGeometry& geometry,
                          const FrictionLaw& friction, double effective_mass);

/// The support's modes at the bodies' initial state (append_penalty_modes).
void append_gap_support_modes(std::span<const core::Body> bodies, int body,
                              const GapSupportGeometry& geometry, const NormalLaw& normal,
                              const FrictionLaw& friction, double effective_mass,
                              std::vector<core::PenaltyMode>& modes);

/// The checks of a gap support's wear law: a name, a circular support, the law's own
/// (core::validate_wear_law).
void validate_gap_support_wear(const core::WearLaw& wear, const GapSupportGeometry& geometry,
                               const std::string& name);

/// The geometry in S (GapGeometryTpl), its unit vectors normalized again in S.
template <typename S>
GapGeometryTpl<S> gap_geometry_in(const GapSupportGeometry& geometry) {
  GapGeometryTpl<S> g;
  g.circular = geometry.kind == GapSupportGeometry::Kind::kCircular;
  g.p_WS = geometry.p_WS.cast<S>();
  g.a_W = core::unit_vector_as<S>(geometry.a_W);
  g.m_W = core::unit_vector_as<S>(geometry.m_W);
  g.clearance = S(geometry.clearance);
  return g;
}

}  // namespace detail

template <typename S>
GapSupportTpl<S>::GapSupportTpl(int body, const Vector3& p_BoN_B, core::NodeAttachmentTpl<S> node,
                                GapSupportGeometry geometry, NormalLaw normal, FrictionLaw friction,
                                double effective_mass, std::string name,
                                std::optional<core::WearLaw> wear)
    : body_(body),
      p_BoN_B_(p_BoN_B),
      node_(std::move(node)),
      geometry_(std::move(geometry)),
      normal_(std::move(normal)),
      friction_(friction),
      effective_mass_(effective_mass),
      name_(std::move(name)),
      wear_(std::move(wear)) {
  detail::validate_gap_support(body_, p_BoN_B_.template cast<double>(), geometry_, friction_,
                               effective_mass_);
  if (wear_) detail::validate_gap_support_wear(*wear_, geometry_, name_);
  geometry_in_s_ = detail::gap_geometry_in<S>(geometry_);
  set_sector_basis();
}

template <typename S>
template <typename U>
GapSupportTpl<S>::GapSupportTpl(const GapSupportTpl<U>& other)
    : body_(other.body_),
      p_BoN_B_(other.p_BoN_B_.template cast<S>()),
      node_(other.node_),
      geometry_(other.geometry_),
      geometry_in_s_(detail::gap_geometry_in<S>(other.geometry_)),
      normal_(other.normal_),
      friction_(other.friction_),
      effective_mass_(other.effective_mass_),
      name_(other.name_),
      wear_(other.wear_) {
  set_sector_basis();
}

template <typename S>
void GapSupportTpl<S>::set_sector_basis() {
  // e1: the first world axis least aligned with a (exactly ⊥ for an axis along a world axis),
  // projected normal to a in double and normalized again in S; e2 = a × e1.
  const Eigen::Vector3d& a = geometry_.a_W;
  int best = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(a(k)) < std::abs(a(best))) best = k;
  }
  const Eigen::Vector3d axis = Eigen::Vector3d::Unit(best);
  const Eigen::Vector3d e1 = axis - a.dot(axis) * a;
  e1_W_ = core::unit_vector_as<S>(e1);
  e2_W_ = core::unit_vector_as<S>(a.cross(e1));
  if (!wear_) return;
  initial_depth_.assign(static_cast<std::size_t>(wear_->sectors), S(0));
  for (std::size_t j = 0; j < wear_->initial_depth.size(); ++j) {
    initial_depth_[j] = S(wear_->initial_depth[j]);
  }
}

template <typename S>
S GapSupportTpl<S>::sector_angle(const Vector3& p_WN) const {
  using std::atan2;
  const Vector3 r = p_WN - geometry_in_s_.p_WS;
  return atan2(e2_W_.dot(r), e1_W_.dot(r));
}

template <typename S>
std::span<const S> GapSupportTpl<S>::worn_depths(const Context& context) const {
  if (wear_->geometry_frozen || context.wear_depth.empty()) return initial_depth_;
  return context.wear_depth;
}

template <typename S>
typename GapSupportTpl<S>::Point GapSupportTpl<S>::gap_point(
    std::span<const Kinematics> bodies) const {
  Point c;
  c.p_WN = core::attached_position_W<S>(bodies[static_cast<std::size_t>(body_)], p_BoN_B_, node_);
  const GapPointTpl<S> g = gap_point_tpl<S>(geometry_in_s_, c.p_WN);
  c.gap = g.gap;
  c.n_W = g.n_W;
  return c;
}

template <typename S>
typename GapSupportTpl<S>::Evaluation GapSupportTpl<S>::evaluate_worn(
    const Context& context, std::span<const Kinematics> bodies, bool loaded_only) const {
  using std::sqrt;
  const auto b = static_cast<std::size_t>(body_);
  const GapGeometryTpl<S>& g = geometry_in_s_;
  Evaluation e;
  e.point.p_WN = core::attached_position_W<S>(bodies[b], p_BoN_B_, node_);
  const Vector3 r = e.point.p_WN - g.p_WS;
  const Vector3 d = r - g.a_W.dot(r) * g.a_W;  // (I − a aᵀ) r
  const S rho = sqrt(d.squaredNorm());
  e.profile = worn_profile_weights<S>(sector_angle(e.point.p_WN), wear_->sectors);
  const std::array<S, 2> h = worn_profile_at<S>(e.profile, worn_depths(context));
  // On the axis there is no direction, and no force (g = c + h > 0).
  if (!(rho > S(0))) {
    e.point.gap = g.clearance + h[0];
    e.point.n_W = g.m_W;
    return e;
  }
  // δ = |d| − c − h(φ),  ∇δ = e_r − (h'/|d|) e_φ,  n = −∇δ/|∇δ|
  const Vector3 e_r = d / rho;
  const Vector3 grad = e_r - (h[1] / rho) * Vector3(g.a_W.cross(e_r));
  e.gradient_norm = sqrt(grad.squaredNorm());
  e.point.gap = g.clearance + h[0] - rho;
  e.point.n_W = -grad / e.gradient_norm;
  const Vector3 v = core::attached_velocity_W<S>(bodies[b], e.point.p_WN, node_);
  e.delta_dot = grad.dot(v);  // δ̇ = ∇δ·v_N of the bodies' motion
  if (loaded_only && e.point.gap >= S(0)) return e;
  // The hole recedes at the point at ḣ(φ) = Σ b_m ḣ_{s_m}, ḣ_j = (deposit on j) V̇ / A_s: the
  // profile's share of the deposit.
  const int j = e.profile.sector[1];
  const int j1 = e.profile.sector[2];
  S share = S(0);
  for (std::size_t m = 0; m < 4; ++m) {
    const int k = e.profile.sector[m];
    share += e.profile.value[m] *
             ((k == j ? e.profile.deposit[0] : S(0)) + (k == j1 ? e.profile.deposit[1] : S(0)));
  }
  const S delta_dot = e.delta_dot;
  static_cast<WornPenaltyLoadTpl<S>&>(e) =
      worn_penalty_load_tpl<S>(normal_, friction_, *wear_, e.point.gap, e.point.n_W, delta_dot, v,
                               e.gradient_norm, share / S(wear_->sector_area()));
  e.delta_dot = delta_dot;  // also while separated (the clamp function)
  if (e.point.gap >= S(0)) e.v_t_W = v - e.point.n_W.dot(v) * e.point.n_W;
  return e;
}

template <typename S>
typename GapSupportTpl<S>::Evaluation GapSupportTpl<S>::evaluate(
    std::span<const Kinematics> bodies) const {
  return evaluate(Context{}, bodies);
}

template <typename S>
typename GapSupportTpl<S>::Evaluation GapSupportTpl<S>::evaluate(
    const Context& context, std::span<const Kinematics> bodies) const {
  if (wear_) return evaluate_worn(context, bodies, true);
  Evaluation e;
  e.point = gap_point(bodies);
  if (e.point.gap >= S(0)) return e;
  const Vector3 v =
      core::attached_velocity_W<S>(bodies[static_cast<std::size_t>(body_)], e.point.p_WN, node_);
  static_cast<PenaltyLoadTpl<S>&>(e) =
      penalty_load_tpl<S>(normal_, friction_, e.point.gap, e.point.n_W, v);
  return e;
}

template <typename S>
void GapSupportTpl<S>::add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                                    std::span<core::WrenchTpl<S>> wrenches) const {
  const Evaluation e = evaluate(context, bodies);
  if (e.normal.total == S(0)) return;
  const auto b = static_cast<std::size_t>(body_);
  core::add_attached_force<S>(bodies[b], node_, e.force_W(), e.point.p_WN, wrenches[b]);
}

template <typename S>
S GapSupportTpl<S>::potential_energy(const Context& context,
                                     std::span<const Kinematics> bodies) const {
  const S gap = wear_ ? evaluate_worn(context, bodies, true).point.gap : gap_point(bodies).gap;
  return normal_.potential_in(S(-gap));
}

template <typename S>
S GapSupportTpl<S>::dissipated_power(const Context& context,
                                     std::span<const Kinematics> bodies) const {
  const Evaluation e = evaluate(context, bodies);
  // and on a wearing hole the spring energy its recession releases, F_e ḣ(φ)
  return wear_ ? e.dissipated_power() + e.normal.elastic * e.recession : e.dissipated_power();
}

template <typename S>
void GapSupportTpl<S>::switching_functions(const Context& context,
                                           std::span<const Kinematics> bodies,
                                           std::span<S> g) const {
  g[0] = wear_ ? evaluate_worn(context, bodies, true).point.gap : gap_point(bodies).gap;
}

template <typename S>
void GapSupportTpl<S>::clamp_functions(const Context& context, std::span<const Kinematics> bodies,
                                       std::span<S> values) const {
  if (wear_) {
    const Evaluation e = evaluate_worn(context, bodies, true);
    values[0] = normal_.clamp_function(S(-e.point.gap), e.delta_dot);
    return;
  }
  const Point p = gap_point(bodies);
  const Vector3 v =
      core::attached_velocity_W<S>(bodies[static_cast<std::size_t>(body_)], p.p_WN, node_);
  values[0] = normal_.clamp_function(S(-p.gap), S(-p.n_W.dot(v)));
}

template <typename S>
void GapSupportTpl<S>::add_wrenches_and_rates(const Context& context,
                                              std::span<const Kinematics> bodies,
                                              std::span<core::WrenchTpl<S>> wrenches, S* dissipated,
                                              std::span<core::WearSampleTpl<S>> wear,
                                              std::span<S> gaps, std::span<S> clamps) const {
  using std::abs;
  using std::sqrt;
  // evaluate()'s load, with the point's velocity also while separated (the clamp function).
  const auto b = static_cast<std::size_t>(body_);
  Evaluation e;
  if (wear_) {
    e = evaluate_worn(context, bodies, false);
    if (!clamps.empty()) clamps[0] = normal_.clamp_function(S(-e.point.gap), e.delta_dot);
  } else {
    e.point = gap_point(bodies);
    const Vector3 v = core::attached_velocity_W<S>(bodies[b], e.point.p_WN, node_);
    static_cast<PenaltyLoadTpl<S>&>(e) =
        penalty_load_tpl<S>(normal_, friction_, e.point.gap, e.point.n_W, v);
    if (!clamps.empty()) {
      clamps[0] = normal_.clamp_function(S(-e.point.gap), S(-e.point.n_W.dot(v)));
    }
  }
  if (!gaps.empty()) gaps[0] = e.point.gap;
  if (dissipated != nullptr) {
    *dissipated +=
        wear_ ? e.dissipated_power() + e.normal.elastic * e.recession : e.dissipated_power();
  }
  if (!wear.empty()) {
    core::WearSampleTpl<S>& w = wear[0];
    w = core::WearSampleTpl<S>{};
    if (e.normal.total != S(0)) {
      w.normal_force = e.normal_force();
      w.slip_speed = sqrt(e.v_t_W.squaredNorm());
      w.wear_power = abs(e.f_friction_W.dot(e.v_t_W));
    }
  }
  if (e.normal.total == S(0)) return;
  core::add_attached_force<S>(bodies[b], node_, e.force_W(), e.point.p_WN, wrenches[b]);
}

template <typename S>
void GapSupportTpl<S>::wear_samples(const Context& context, std::span<const Kinematics> bodies,
                                    std::span<core::WearSampleTpl<S>> samples) const {
  using std::abs;
  using std::sqrt;
  const Evaluation e = evaluate(context, bodies);
  core::WearSampleTpl<S>& w = samples[0];
  w = core::WearSampleTpl<S>{};
  if (e.normal.total == S(0)) return;
  w.normal_force = e.normal_force();
  w.slip_speed = sqrt(e.v_t_W.squaredNorm());
  w.wear_power = abs(e.f_friction_W.dot(e.v_t_W));  // |F_t·v_t|
}

template <typename S>
void GapSupportTpl<S>::wear_depth_rates(const Context& context, std::span<const Kinematics> bodies,
                                        std::span<S> rates) const {
  for (S& r : rates) r = S(0);
  const Evaluation e = evaluate_worn(context, bodies, true);
  if (e.normal.total == S(0)) return;
  // ḣ_j = w_j V̇ / A_s on the two sectors bracketing the contact's angle.
  const S rate = e.volume_rate / S(wear_->sector_area());
  rates[static_cast<std::size_t>(e.profile.sector[1])] += e.profile.deposit[0] * rate;
  rates[static_cast<std::size_t>(e.profile.sector[2])] += e.profile.deposit[1] * rate;
}

template <typename S>
std::string GapSupportTpl<S>::describe() const {
  return describe_with_names(std::span<const core::Body>{});
}

template <typename S>
std::string GapSupportTpl<S>::describe_with_names(std::span<const core::Body> bodies) const {
  std::ostringstream out;
  const bool circular = geometry_.kind == GapSupportGeometry::Kind::kCircular;
  out << "gap support: " << (circular ? "circular" : "planar") << " clearance "
      << geometry_.clearance << " m around the axis through (" << geometry_.p_WS.transpose()
      << ") along (" << geometry_.a_W.transpose() << ")";
  if (!circular) out << ", planes normal to (" << geometry_.m_W.transpose() << ")";
  out << ", at " << core::body_text(body_, bodies) << " "
      << (node_.deforms() ? core::node_text(body_, node_.node, bodies) : std::string("point"))
      << ", " << normal_.describe() << ", friction mu = " << friction_.mu
      << ", v_reg = " << friction_.v_reg << " m/s";
  if (!name_.empty()) out << ", wear outputs '" << name_ << "'";
  if (wear_) out << "; " << wear_->describe();
  return out.str();
}

template <typename S>
void GapSupportTpl<S>::append_penalty_modes(std::span<const core::Body> bodies,
                                            std::vector<core::PenaltyMode>& modes) const {
  detail::append_gap_support_modes(bodies, body_, geometry_, normal_, friction_, effective_mass_,
                                   modes);
}

}  // namespace flexref::contact
