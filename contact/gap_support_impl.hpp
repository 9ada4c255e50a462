#pragma once
/// \file gap_support_impl.hpp
/// The definitions of gap_support.hpp's class template, included where it is instantiated:
/// gap_support.cpp (double) and precision/element_conversion.cpp (long double, float128).
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

/// The geometry in S (GapGeometryTpl), its unit vectors normalized again in S.
template <typename S>
GapGeometryTpl<S> gap_geometry_in(const GapSupportGeometry& geometry) {
  GapGeometryTpl<S> g;
  g.circular = geometry.kind == GapSupportGeometry::Kind::kCircular;
  g.p_WS = geometry.p_WS.cast<S>();
  g.a_W = core::unit_vector_in<S>(geometry.a_W);
  g.m_W = core::unit_vector_in<S>(geometry.m_W);
  g.clearance = S(geometry.clearance);
  return g;
}

}  // namespace detail

template <typename S>
GapSupportTpl<S>::GapSupportTpl(int body, const Vector3& p_BoN_B, core::NodeAttachmentTpl<S> node,
                                GapSupportGeometry geometry, NormalLaw normal, FrictionLaw friction,
                                double effective_mass, std::string name)
    : body_(body),
      p_BoN_B_(p_BoN_B),
      node_(std::move(node)),
      geometry_(std::move(geometry)),
      normal_(std::move(normal)),
      friction_(friction),
      effective_mass_(effective_mass),
      name_(std::move(name)) {
  detail::validate_gap_support(body_, p_BoN_B_.template cast<double>(), geometry_, friction_,
                               effective_mass_);
  geometry_in_s_ = detail::gap_geometry_in<S>(geometry_);
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
      name_(other.name_) {}

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
typename GapSupportTpl<S>::Evaluation GapSupportTpl<S>::evaluate(
    std::span<const Kinematics> bodies) const {
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
void GapSupportTpl<S>::add_wrenches(const Context& /*context*/, std::span<const Kinematics> bodies,
                                    std::span<core::WrenchTpl<S>> wrenches) const {
  const Evaluation e = evaluate(bodies);
  if (e.normal.total == S(0)) return;
  const auto b = static_cast<std::size_t>(body_);
  core::add_attached_force<S>(bodies[b], node_, e.force_W(), e.point.p_WN, wrenches[b]);
}

template <typename S>
S GapSupportTpl<S>::potential_energy(const Context& /*context*/,
                                     std::span<const Kinematics> bodies) const {
  return normal_.potential_in(S(-gap_point(bodies).gap));
}

template <typename S>
S GapSupportTpl<S>::dissipated_power(const Context& /*context*/,
                                     std::span<const Kinematics> bodies) const {
  return evaluate(bodies).dissipated_power();
}

template <typename S>
void GapSupportTpl<S>::switching_functions(const Context& /*context*/,
                                           std::span<const Kinematics> bodies,
                                           std::span<S> g) const {
  g[0] = gap_point(bodies).gap;
}

template <typename S>
void GapSupportTpl<S>::clamp_functions(const Context& /*context*/,
                                       std::span<const Kinematics> bodies,
                                       std::span<S> values) const {
  const Point p = gap_point(bodies);
  const Vector3 v =
      core::attached_velocity_W<S>(bodies[static_cast<std::size_t>(body_)], p.p_WN, node_);
  values[0] = normal_.clamp_function(S(-p.gap), S(-p.n_W.dot(v)));
}

template <typename S>
void GapSupportTpl<S>::add_wrenches_and_rates(const Context& /*context*/,
                                              std::span<const Kinematics> bodies,
                                              std::span<core::WrenchTpl<S>> wrenches, S* dissipated,
                                              std::span<core::WearSampleTpl<S>> wear,
                                              std::span<S> gaps, std::span<S> clamps) const {
  using std::abs;
  using std::sqrt;
  // evaluate()'s load, with the point's velocity also while separated (the clamp function).
  const auto b = static_cast<std::size_t>(body_);
  Evaluation e;
  e.point = gap_point(bodies);
  const Vector3 v = core::attached_velocity_W<S>(bodies[b], e.point.p_WN, node_);
  static_cast<PenaltyLoadTpl<S>&>(e) =
      penalty_load_tpl<S>(normal_, friction_, e.point.gap, e.point.n_W, v);
  if (!gaps.empty()) gaps[0] = e.point.gap;
  if (!clamps.empty()) clamps[0] = normal_.clamp_function(S(-e.point.gap), S(-e.point.n_W.dot(v)));
  if (dissipated != nullptr) *dissipated += e.dissipated_power();
  if (!wear.empty()) {
    core::WearSampleTpl<S>& w = wear[0];
    w = core::WearSampleTpl<S>{};
    if (e.normal.total != S(0)) {
      w.normal_force = e.normal.total;
      w.slip_speed = sqrt(e.v_t_W.squaredNorm());
      w.wear_power = abs(e.f_friction_W.dot(e.v_t_W));
    }
  }
  if (e.normal.total == S(0)) return;
  core::add_attached_force<S>(bodies[b], node_, e.force_W(), e.point.p_WN, wrenches[b]);
}

template <typename S>
void GapSupportTpl<S>::wear_samples(const Context& /*context*/, std::span<const Kinematics> bodies,
                                    std::span<core::WearSampleTpl<S>> samples) const {
  using std::abs;
  using std::sqrt;
  const Evaluation e = evaluate(bodies);
  core::WearSampleTpl<S>& w = samples[0];
  w = core::WearSampleTpl<S>{};
  if (e.normal.total == S(0)) return;
  w.normal_force = e.normal.total;
  w.slip_speed = sqrt(e.v_t_W.squaredNorm());
  w.wear_power = abs(e.f_friction_W.dot(e.v_t_W));  // |F_t·v_t|
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
  return out.str();
}

template <typename S>
void GapSupportTpl<S>::append_penalty_modes(std::span<const core::Body> bodies,
                                            std::vector<core::PenaltyMode>& modes) const {
  detail::append_gap_support_modes(bodies, body_, geometry_, normal_, friction_, effective_mass_,
                                   modes);
}

}  // namespace flexref::contact
