#pragma once
/// \file body_equations_tpl.hpp
/// The right-hand sides of one body's equations from its loads, written once for any scalar
/// type S: core::ModelTpl<S> evaluates them in double for the integrators, in extended and quad
/// for the precision references. docs/design/model.md, quasi-velocity form about Br, v = (a_WBr, α̅,
/// q̈_f):
///   rigid (the paper's eqs. 24–25):  I_Br α̅ = Aᵀ τ_Br − ω̄ × I_Br ω̄,
///   flexible:  M v = Qe + Qv − [0; 0; K q_f + D q̇_f],  Qe = (f_W, Aᵀ τ_Br_W, Q_f),
/// with Qv the quadratic velocity terms of flexible/inertia_terms_tpl.hpp, and their solution for
/// the unknown accelerations: the rows a body's motion fixes (pivot: a = 0; prescribed: a = 0 and
/// the angle law's α̅) are known, the others are solved in O(n²) through m_ff's constant factor
/// (flexible/mass_matrix_solve_tpl.hpp). Under LTE the inertia terms are the undeformed body's.
#include <Eigen/Core>

#include "core/body.hpp"
#include "core/flexible_formulation.hpp"
#include "core/force_element.hpp"
#include "core/state.hpp"
#include "flexible/inertia_terms_tpl.hpp"
#include "flexible/mass_matrix_solve_tpl.hpp"

namespace flexref::core {

/// α̅ of a rigid body about Br from the torque about Br (world): I_Br⁻¹ (Aᵀ τ − ω̄ × I_Br ω̄) (I_Br:
/// the inertia about Br, body frame).
template <typename S>
Eigen::Matrix<S, 3, 1> euler_angular_acceleration_tpl(const Eigen::Matrix<S, 3, 3>& I_Br_B,
                                                      const Eigen::Matrix<S, 3, 3>& I_Br_B_inverse,
                                                      const Eigen::Matrix<S, 3, 3>& R_WB,
                                                      const Eigen::Matrix<S, 3, 1>& tau_Br_W,
                                                      const Eigen::Matrix<S, 3, 1>& w_WB_B) {
  const Eigen::Matrix<S, 3, 1> tau_B = R_WB.transpose() * tau_Br_W;
  return I_Br_B_inverse * (tau_B - w_WB_B.cross(I_Br_B * w_WB_B));
}

/// rhs (6 + n) = Qe + Qv − [0; 0; K q_f + D q̇_f] of a flexible body (K, D: the diagonal modal
/// stiffness and damping). Allocates nothing.
template <typename S>
void flexible_right_hand_side_tpl(
    const Eigen::Matrix<S, 3, 1>& f_W, const Eigen::Matrix<S, 3, 1>& tau_Br_W,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& Q_f,
    const Eigen::Matrix<S, 3, 3>& R_WB,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& Qv,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& stiffness,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& damping,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& q_f,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& qd_f,
    Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> rhs) {
  const Eigen::Index n = q_f.size();
  rhs.template head<3>() = f_W + Qv.template head<3>();
  rhs.template segment<3>(3) = R_WB.transpose() * tau_Br_W + Qv.template segment<3>(3);
  rhs.tail(n) = Q_f + Qv.tail(n) - stiffness.cwiseProduct(q_f) - damping.cwiseProduct(qd_f);
}

/// The generalized-velocity rows a body's motion fixes, first: free none, pivot a = 0 (3),
/// prescribed a = 0 and the law's α̅ (6).
inline int known_rows(MotionKind motion) {
  switch (motion) {
    case MotionKind::kFree:
      return 0;
    case MotionKind::kPivot:
      return 3;
    case MotionKind::kPrescribed:
      return 6;
  }
  return 0;
}

/// a_WBr and α̅ of a rigid body about Br from the loads on it: m a = f for a free body (Br = Bcm),
/// a = 0 on a pivot, Euler's equations (paper eqs. 24–25) for both; a prescribed body's are its
/// law's (a = 0, α̅ = alpha_law_B).
template <typename S>
void rigid_body_accelerations_tpl(MotionKind motion, const S& mass,
                                  const Eigen::Matrix<S, 3, 3>& I_Br_B,
                                  const Eigen::Matrix<S, 3, 3>& I_Br_B_inverse,
                                  const Eigen::Matrix<S, 3, 3>& R_WB, const WrenchTpl<S>& wrench,
                                  const Eigen::Matrix<S, 3, 1>& w_WB_B,
                                  const Eigen::Matrix<S, 3, 1>& alpha_law_B,
                                  Eigen::Matrix<S, 3, 1>& a_WBr,
                                  Eigen::Matrix<S, 3, 1>& alpha_WB_B) {
  if (motion == MotionKind::kPrescribed) {
    a_WBr.setZero();
    alpha_WB_B = alpha_law_B;
    return;
  }
  if (motion == MotionKind::kFree) {
    a_WBr = wrench.f_W / mass;
  } else {
    a_WBr.setZero();
  }
  alpha_WB_B =
      euler_angular_acceleration_tpl<S>(I_Br_B, I_Br_B_inverse, R_WB, wrench.tau_Br_W, w_WB_B);
}

/// A flexible body's system at its state: the inertia terms M_rr, M_rf, Qv (coupled: at the
/// state's q_f, q̇_f; LTE: of the undeformed body, `zero` holding n zeros) and rhs (6 + n) =
/// Qe + Qv − [0; 0; K q_f + D q̇_f] from the loads on it. Allocates nothing.
template <typename S>
void flexible_system_tpl(const flexible::ModalInvariantsTpl<S>& invariants,
                         FlexibleFormulation formulation, const Eigen::Matrix<S, 3, 3>& R_WB,
                         const BodyStateTpl<S>& state,
                         const Eigen::Matrix<S, Eigen::Dynamic, 1>& zero,
                         const WrenchTpl<S>& wrench,
                         const Eigen::Matrix<S, Eigen::Dynamic, 1>& stiffness,
                         const Eigen::Matrix<S, Eigen::Dynamic, 1>& damping,
                         flexible::InertiaTermsTpl<S>& terms,
                         Eigen::Matrix<S, Eigen::Dynamic, 1>& rhs) {
  if (formulation == FlexibleFormulation::kLte) {
    flexible::set_undeformed_products_tpl<S>(terms);
    flexible::assemble_inertia_terms_tpl<S>(invariants, R_WB, zero, state.w_WB_B, zero, terms);
  } else {
    flexible::compute_modal_products_tpl<S>(invariants, state.q_f, state.qd_f, terms);
    flexible::assemble_inertia_terms_tpl<S>(invariants, R_WB, state.q_f, state.w_WB_B, state.qd_f,
                                            terms);
  }
  flexible_right_hand_side_tpl<S>(wrench.f_W, wrench.tau_Br_W, wrench.Q_f, R_WB, terms.Qv,
                                  stiffness, damping, state.q_f, state.qd_f, rhs);
}

/// x = (a_WBr, α̅, q̈_f) of a flexible body from its system (flexible_system_tpl): the known rows
/// (known_rows(motion); a prescribed body's α̅ = alpha_law_B) set, the others solved — coupled by
/// the Schur complement of the unknown rigid rows, LTE by block forward substitution
/// (flexible/mass_matrix_solve.hpp). A singular rigid block leaves NaN in x (the integrators
/// reject the step).
template <typename S>
void solve_flexible_accelerations_tpl(const flexible::ModalMassFactorTpl<S>& factor,
                                      FlexibleFormulation formulation,
                                      const flexible::InertiaTermsTpl<S>& terms, MotionKind motion,
                                      const Eigen::Matrix<S, 3, 1>& alpha_law_B,
                                      const Eigen::Matrix<S, Eigen::Dynamic, 1>& rhs,
                                      flexible::MassSolveScratchTpl<S>& solve,
                                      Eigen::Matrix<S, Eigen::Dynamic, 1>& x) {
  const int known = known_rows(motion);
  x.template head<6>().setZero();
  if (motion == MotionKind::kPrescribed) x.template segment<3>(3) = alpha_law_B;
  if (formulation == FlexibleFormulation::kCoupled) {
    flexible::factor_coupled_tpl<S>(factor, terms, known, solve);
    flexible::apply_coupled_tpl<S>(factor, terms, rhs, solve, x);
  } else {
    flexible::factor_lte_tpl<S>(terms, known, solve);
    flexible::apply_lte_tpl<S>(factor, terms, rhs, solve, x);
  }
}

}  // namespace flexref::core
