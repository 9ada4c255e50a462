#pragma once
/// \file gravity_impl.hpp
/// The definitions of gravity.hpp's class template, included where it is instantiated:
/// gravity.cpp (double) and precision/element_conversion.cpp (long double, float128).
#include <algorithm>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/gravity.hpp"
#include "flexible/geometric_stiffness_tpl.hpp"
#include "flexible/modal_invariants_tpl.hpp"

namespace flexref::core {

// Uniform gravity's generalized loads and potential on a body given by its invariants about its
// reference point Br (a rigid body takes m g at its centre of mass). docs/design/model.md:
//   Qe_R += m g,   Qe_θ += s̃_t Aᵀ g (τ_Br_W += A (s_t × Aᵀ g)),   Qe_f += Sᵀ Aᵀ g,
// with s_t = s0 + S q_f − ½ [q·E_c q]_c the first moment about Br (modal_invariants_tpl.hpp,
// GS-4), and under geometric stiffening the foreshortening's work Qe_f += ΔS(q_f)ᵀ Aᵀ g
// (docs/geometric_stiffening.md: a freely falling body carries no axial load). The potential is
// V = −g·Σ m_k r_k = −g·(m p_WBr + A s_t). q_f is what the loads see: the state's under the
// coupled model, zero under LTE.

/// Adds gravity's loads on one body to f_W, τ_Br_W (world) and Q_f. Allocates nothing.
template <typename S>
void add_gravity_loads_tpl(const flexible::ModalInvariantsTpl<S>& inv,
                           const Eigen::Matrix<S, 3, 3>& R_WB,
                           const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& q_f,
                           const Eigen::Matrix<S, 3, 1>& g_W, Eigen::Matrix<S, 3, 1>& f_W,
                           Eigen::Matrix<S, 3, 1>& tau_Br_W,
                           Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> Q_f) {
  if (q_f.size() != inv.S.cols() || Q_f.size() != inv.S.cols()) {
    throw std::invalid_argument("gravity: q_f or Q_f does not have one entry per mode");
  }
  const Eigen::Matrix<S, 3, 1> g_B = R_WB.transpose() * g_W;
  const Eigen::Matrix<S, 3, 1> s_t = flexible::first_moment_tpl<S>(inv, q_f);
  f_W += inv.mass * g_W;
  tau_Br_W += R_WB * s_t.cross(g_B);
  Q_f.noalias() += inv.S.transpose() * g_B;
  if (inv.geometric) {
    flexible::add_foreshortening_first_moment_transpose_tpl<S>(*inv.geometric, q_f, g_B, Q_f);
  }
}

/// Gravity's potential energy of one body, −g·(m p_WBr + A s_t).
template <typename S>
S gravity_potential_tpl(const flexible::ModalInvariantsTpl<S>& inv,
                        const Eigen::Matrix<S, 3, 3>& R_WB, const Eigen::Matrix<S, 3, 1>& p_WBr,
                        const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& q_f,
                        const Eigen::Matrix<S, 3, 1>& g_W) {
  return -g_W.dot(inv.mass * p_WBr + R_WB * flexible::first_moment_tpl<S>(inv, q_f));
}

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
    // Flexible: add_gravity_loads_tpl on the invariants about Br.
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
