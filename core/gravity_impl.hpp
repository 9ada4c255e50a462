#pragma once
/// \file gravity_impl.hpp
/// The definitions of gravity.hpp's class template, included where it is instantiated:
/// gravity.cpp (double) and precision/element_conversion.cpp (long double, float128).
#include <algorithm>
#include <cstddef>
#include <sstream>
#include <utility>

#include "core/gravity.hpp"
#include "core/gravity_tpl.hpp"

namespace flexref::core {

template <typename S>
UniformGravityTpl<S>::UniformGravityTpl(const Vector3& g_W, std::vector<BodyMass> bodies)
    : g_W_(g_W), bodies_(std::move(bodies)) {}

template <typename S>
template <typename U>
UniformGravityTpl<S>::UniformGravityTpl(const UniformGravityTpl<U>& other)
    : g_W_(other.g_W_.template cast<S>()) {
  for (const auto& b : other.bodies_) {
    bodies_.push_back({b.body, S(b.mass), b.p_BoBcm_B.template cast<S>()});
  }
}

template <typename S>
void UniformGravityTpl<S>::add_wrenches(const Context& /*context*/,
                                        std::span<const Kinematics> bodies,
                                        std::span<WrenchTpl<S>> wrenches) const {
  for (const BodyMass& b : bodies_) {
    const auto i = static_cast<std::size_t>(b.body);
    const Kinematics& k = bodies[i];
    if (k.invariants == nullptr) {
      wrenches[i].add_force_at(b.mass * g_W_, k.p_BrP_W(b.p_BoBcm_B));
      continue;
    }
    // Flexible: the loads of core/gravity_tpl.hpp on the invariants about Br.
    add_gravity_loads_tpl<S>(*k.invariants, k.R_WB, *k.q_f, g_W_, wrenches[i].f_W,
                             wrenches[i].tau_Br_W, wrenches[i].Q_f);
  }
}

template <typename S>
S UniformGravityTpl<S>::potential_energy(const Context& /*context*/,
                                         std::span<const Kinematics> bodies) const {
  S v(0);
  for (const BodyMass& b : bodies_) {
    const Kinematics& k = bodies[static_cast<std::size_t>(b.body)];
    if (k.invariants == nullptr) {
      v -= b.mass * g_W_.dot(k.p_WP(b.p_BoBcm_B));
    } else {
      v += gravity_potential_tpl<S>(*k.invariants, k.R_WB, k.state->p_WBr, *k.q_f, g_W_);
    }
  }
  return v;
}

template <typename S>
int UniformGravityTpl<S>::max_body_index() const {
  int m = -1;
  for (const BodyMass& b : bodies_) m = std::max(m, b.body);
  return m;
}

template <typename S>
std::string UniformGravityTpl<S>::describe() const {
  std::ostringstream out;
  out << "gravity (" << g_W_.x() << ", " << g_W_.y() << ", " << g_W_.z() << ") m/s^2 on "
      << bodies_.size() << " bodies";
  return out.str();
}

}  // namespace flexref::core
