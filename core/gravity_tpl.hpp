#pragma once
/// \file gravity_tpl.hpp
/// Uniform gravity's generalized loads and potential on a body given by its invariants about its
/// reference point Br, written once for any scalar type S: core::UniformGravityTpl<S> evaluates
/// its flexible bodies with it in every precision (a rigid body takes m g at its centre of mass).
/// docs/design/model.md:
///   Qe_R += m g,   Qe_θ += s̃_t Aᵀ g (τ_Br_W += A (s_t × Aᵀ g)),   Qe_f += Sᵀ Aᵀ g,
/// with s_t = s0 + S q_f − ½ [q·E_c q]_c the first moment about Br (modal_invariants_tpl.hpp,
/// GS-4), and under geometric stiffening the foreshortening's work Qe_f += ΔS(q_f)ᵀ Aᵀ g
/// (docs/geometric_stiffening.md: a freely falling body carries no axial load). The potential is
/// V = −g·Σ m_k r_k = −g·(m p_WBr + A s_t). q_f is what the loads see: the state's under the
/// coupled model, zero under LTE.
#include <Eigen/Core>
#include <stdexcept>

#include "flexible/geometric_stiffness_tpl.hpp"
#include "flexible/modal_invariants_tpl.hpp"

namespace flexref::core {

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

}  // namespace flexref::core
