#pragma once
/// \file body_equations_tpl.hpp
/// The right-hand sides of one body's equations from its loads, written once for any scalar
/// type S: core::Model evaluates them in double, precision::MultibodyModelTpl in extended and
/// quad. docs/design/model.md, quasi-velocity form about Br, v = (a_WBr, α̅, q̈_f):
///   rigid (the paper's eqs. 24–25):  I_Br α̅ = Aᵀ τ_Br − ω̄ × I_Br ω̄,
///   flexible:  M v = Qe + Qv − [0; 0; K q_f + D q̇_f],  Qe = (f_W, Aᵀ τ_Br_W, Q_f),
/// with Qv the quadratic velocity terms of flexible/inertia_terms_tpl.hpp.
#include <Eigen/Core>

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

}  // namespace flexref::core
