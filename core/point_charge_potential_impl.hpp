#pragma once
/// \file point_charge_potential_impl.hpp
/// The definitions of point_charge_potential.hpp's class template, included where it is
/// instantiated: point_charge_potential.cpp (double) and precision/element_conversion.cpp (long
/// double, float128).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <utility>

#include "core/point_charge_potential.hpp"

namespace flexref::core {

template <typename S>
PointChargePotentialTpl<S>::PointChargePotentialTpl(S alpha, S beta, const Vector3& p_WM,
                                                    std::vector<Charge> charges)
    : alpha_(alpha), beta_(beta), p_WM_(p_WM), charges_(std::move(charges)) {}

template <typename S>
template <typename U>
PointChargePotentialTpl<S>::PointChargePotentialTpl(const PointChargePotentialTpl<U>& other)
    : alpha_(S(other.alpha_)), beta_(S(other.beta_)), p_WM_(other.p_WM_.template cast<S>()) {
  for (const auto& c : other.charges_) {
    charges_.push_back({c.body, c.p_BoP_B.template cast<S>(), S(c.weight)});
  }
}

template <typename S>
void PointChargePotentialTpl<S>::unit_field(const Vector3& p_WP, Vector3& f_W, S& potential) const {
  using std::sqrt;
  const S d[3] = {p_WP.x() - p_WM_.x(), p_WP.y() - p_WM_.y(), p_WP.z() - p_WM_.z()};
  const S r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const S z = p_WP.z();
  for (int i = 0; i < 3; ++i) f_W(i) = -alpha_ * d[i] / (r * r * r);
  f_W(2) += beta_ / (z * z);
  potential = -alpha_ / r + beta_ / z;
}

template <typename S>
typename PointChargePotentialTpl<S>::Vector3 PointChargePotentialTpl<S>::unit_force_W(
    const Vector3& p_WP) const {
  Vector3 f;
  S v(0);
  unit_field(p_WP, f, v);
  return f;
}

template <typename S>
S PointChargePotentialTpl<S>::unit_potential(const Vector3& p_WP) const {
  Vector3 f;
  S v(0);
  unit_field(p_WP, f, v);
  return v;
}

template <typename S>
void PointChargePotentialTpl<S>::add_wrenches(const Context& /*context*/,
                                              std::span<const Kinematics> bodies,
                                              std::span<WrenchTpl<S>> wrenches) const {
  for (const Charge& c : charges_) {
    const auto i = static_cast<std::size_t>(c.body);
    const Kinematics& body = bodies[i];
    wrenches[i].add_force_at(c.weight * unit_force_W(body.p_WP(c.p_BoP_B)),
                             body.p_BrP_W(c.p_BoP_B));
  }
}

template <typename S>
S PointChargePotentialTpl<S>::potential_energy(const Context& /*context*/,
                                               std::span<const Kinematics> bodies) const {
  S v(0);
  for (const Charge& c : charges_) {
    v += c.weight * unit_potential(bodies[static_cast<std::size_t>(c.body)].p_WP(c.p_BoP_B));
  }
  return v;
}

template <typename S>
int PointChargePotentialTpl<S>::max_body_index() const {
  int m = -1;
  for (const Charge& c : charges_) m = std::max(m, c.body);
  return m;
}

template <typename S>
std::string PointChargePotentialTpl<S>::describe() const {
  std::ostringstream out;
  out << "point-charge potential: alpha " << alpha_ << ", beta " << beta_ << ", attractor ("
      << p_WM_.x() << ", " << p_WM_.y() << ", " << p_WM_.z() << "), wall z = 0, " << charges_.size()
      << " charges";
  return out.str();
}

}  // namespace flexref::core
