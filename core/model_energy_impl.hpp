#pragma once
/// \file model_energy_impl.hpp
/// ModelTpl<S>'s energies, momenta and the world positions of body points (docs/design/model.md,
/// "Energy and momentum"). Included by model_impl.hpp.
#include <type_traits>

#include "core/model.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "flexible/inertia_terms_tpl.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::core {

template <typename S>
S ModelTpl<S>::kinetic_energy(const State& state) const {
  S t = S(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    if (b.is_flexible()) {
      const Eigen::Matrix<S, 3, 3> R_WB = rotation::rotation_matrix<S>(s.theta_WB);
      if constexpr (std::is_same_v<S, double>) {
        t += flexible::flexible_kinetic_energy(b.invariants(), R_WB, s.q_f, s.v_WBr, s.w_WB_B,
                                               s.qd_f);
      } else {
        // ½ vᵀ M v from the mass matrix's blocks at the state's q_f (under LTE too), v = (v_WBr,
        // ω̄, q̇_f): ½ [v_rᵀ M_rr v_r + 2 v_rᵀ M_rf q̇ + q̇ᵀ m_ff q̇]. Double's route
        // (flexible_kinetic_energy) sums the invariants' products without scratch; in S the
        // blocks' scratch is formed here (an output, not an evaluation of the integrators).
        flexible::InertiaTermsTpl<S> terms = flexible::make_inertia_terms_tpl<S>(b.mode_count());
        const Vector zero = Vector::Zero(b.mode_count());
        flexible::compute_modal_products_tpl<S>(b.invariants(), s.q_f, zero, terms);
        flexible::assemble_inertia_terms_tpl<S>(b.invariants(), R_WB, s.q_f, s.w_WB_B, zero, terms);
        Eigen::Matrix<S, 6, 1> v_r;
        v_r << s.v_WBr, s.w_WB_B;
        t += S(0.5) * (v_r.dot(terms.M_rr * v_r) + S(2) * v_r.dot(terms.M_rf * s.qd_f) +
                       s.qd_f.dot(b.invariants().m_ff * s.qd_f));
      }
      continue;
    }
    // T = ½ m |v_Bcm|² + ½ ω̄ᵀ I_Bcm ω̄ (free, Br = Bcm);  T = ½ ω̄ᵀ I_Pv ω̄ (pivot).
    t += S(0.5) * s.w_WB_B.dot(b.I_Br_B() * s.w_WB_B);
    if (b.is_free()) t += S(0.5) * b.mass() * s.v_WBr.squaredNorm();
  }
  return t;
}

template <typename S>
S ModelTpl<S>::potential_energy(const LoadContext& context, const State& state,
                                Workspace& ws) const {
  pose_bodies(state, ws);
  S v = elastic_energy(state);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    v += elements_[e]->potential_energy(element_context(context, ws, e), ws.kinematics);
  }
  return v;
}

template <typename S>
S ModelTpl<S>::elastic_energy(const State& state) const {
  S v = S(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (!bodies_[i].is_flexible()) continue;
    // ½ q_fᵀ K q_f with K = diag(K_i)
    v += S(0.5) * state[i].q_f.dot(bodies_[i].modal_stiffness().cwiseProduct(state[i].q_f));
  }
  return v;
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::linear_momentum_W(
    const State& state) const requires std::is_same_v<S, double> {
  Vector3 p = Vector3::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Eigen::Matrix<S, 3, 3> R_WB = rotation::rotation_matrix<S>(s.theta_WB);
    if (b.is_flexible()) {
      // First row of M v: m Ṙ + A (ω̄ × s_t + S q̇_f)
      const flexible::ModalInvariantsTpl<S>& inv = b.invariants();
      p += inv.mass * s.v_WBr + R_WB * (s.w_WB_B.cross(flexible::first_moment(inv, s.q_f)) +
                                        flexible::first_moment_rate(inv, s.q_f, s.qd_f));
      continue;
    }
    p += b.mass() * (s.v_WBr + R_WB * s.w_WB_B.cross(b.p_BrBcm_B()));
  }
  return p;
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::angular_momentum_W(
    const State& state) const requires std::is_same_v<S, double> {
  // H_O = Σ p_WBr × m v_Bcm + A (I_Br ω̄ + m p_BrBcm × v_Br expressed in B); for a free body
  // (Br = Bcm) and a pivot body (v_Br = 0) the last term vanishes.
  Vector3 h = Vector3::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Eigen::Matrix<S, 3, 3> R_WB = rotation::rotation_matrix<S>(s.theta_WB);
    if (b.is_flexible()) {
      // H_O = p_WBr × p + H_Br,  H_Br = A (s̃_t Aᵀ Ṙ + Ī_θθ ω̄ + Ī_θf q̇_f)  (θ row of M v)
      const flexible::ModalInvariantsTpl<S>& inv = b.invariants();
      const Vector3 s_t = flexible::first_moment(inv, s.q_f);
      const Vector3 p_W =
          inv.mass * s.v_WBr +
          R_WB * (s.w_WB_B.cross(s_t) + flexible::first_moment_rate(inv, s.q_f, s.qd_f));
      const Vector3 h_B = s_t.cross(R_WB.transpose() * s.v_WBr) +
                          flexible::inertia_theta_theta(inv, s.q_f) * s.w_WB_B +
                          flexible::inertia_theta_f(inv, s.q_f) * s.qd_f;
      h += s.p_WBr.cross(p_W) + R_WB * h_B;
      continue;
    }
    const Vector3 v_WBcm = s.v_WBr + R_WB * s.w_WB_B.cross(b.p_BrBcm_B());
    h += s.p_WBr.cross(b.mass() * v_WBcm) + R_WB * (b.I_Br_B() * s.w_WB_B);
  }
  return h;
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::p_WBo(int i, const BodyState& s) const {
  return s.p_WBr - rotation::rotation_matrix<S>(s.theta_WB) * body(i).p_BoBr_B();
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::v_WBo(int i, const BodyState& s) const {
  return s.v_WBr - rotation::rotation_matrix<S>(s.theta_WB) * s.w_WB_B.cross(body(i).p_BoBr_B());
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::p_WP(int i, const BodyState& s,
                                                const Eigen::Vector3d& p_BoP_B) const {
  return s.p_WBr + rotation::rotation_matrix<S>(s.theta_WB) * body(i).p_BrP_B(p_BoP_B);
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::p_WP(int i, const BodyState& s,
                                                const TrackedPoint& point) const {
  return s.p_WBr + rotation::rotation_matrix<S>(s.theta_WB) * body(i).p_BrP_B(point, s.q_f);
}

}  // namespace flexref::core
