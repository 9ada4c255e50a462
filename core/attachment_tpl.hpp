#pragma once
/// \file attachment_tpl.hpp
/// The kinematics and the virtual work of a point attached to a body (core/node_attachment.hpp,
/// docs/modal_data.md "Loads at nodes"), written once for any scalar type S: core's
/// attached_position_W, attached_velocity_W and add_attached_force (core/node_attachment.hpp)
/// call them in every precision. A
/// point at node k moves with the node,
/// ū_P = x_P + Φ_k q_f (body frame, eq. 10); a hub point has no mode shape (phi_B = nullptr):
///   offset:    p_WP − p_WBr = A (x_P − p_BoBr + Φ_k q_f),
///   velocity:  v_WP = v_WBr + ω × (P − p_WBr) + A Φ_k q̇_f   (P: the world point of application),
///   work:      δr_P = δp_WBr + δπ × (P − p_WBr) + A Φ_k δq_f, so Qe_f += Φ_kᵀ Aᵀ f.
#include <Eigen/Core>

namespace flexref::core {

template <typename S>
using AttachmentShape = Eigen::Matrix<S, 3, Eigen::Dynamic>;

/// A (p_BrP_B + Φ_k q_f), the attached point's offset from Br in world; p_BrP_B = x_P − p_BoBr.
template <typename S>
Eigen::Matrix<S, 3, 1> attached_offset_tpl(
    const Eigen::Matrix<S, 3, 3>& R_WB, const Eigen::Matrix<S, 3, 1>& p_BrP_B,
    const AttachmentShape<S>* phi_B,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& q_f) {
  if (phi_B == nullptr) return R_WB * p_BrP_B;
  return R_WB * (p_BrP_B + *phi_B * q_f);
}

/// v_WBr + ω × (P − p_WBr) + A Φ_k q̇_f, the velocity of the material point of the attachment's
/// body at the world point P (ω in world).
template <typename S>
Eigen::Matrix<S, 3, 1> attached_velocity_tpl(
    const Eigen::Matrix<S, 3, 1>& v_WBr, const Eigen::Matrix<S, 3, 1>& w_WB_W,
    const Eigen::Matrix<S, 3, 1>& p_WBr, const Eigen::Matrix<S, 3, 3>& R_WB,
    const AttachmentShape<S>* phi_B,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& qd_f,
    const Eigen::Matrix<S, 3, 1>& p_WP) {
  Eigen::Matrix<S, 3, 1> v = v_WBr + w_WB_W.cross(p_WP - p_WBr);
  if (phi_B != nullptr) v.noalias() += R_WB * (*phi_B * qd_f);
  return v;
}

/// Q_f += Φ_kᵀ Aᵀ f, the modal force of f (world) at a node; nothing at a hub point. Allocates
/// nothing.
template <typename S>
void add_attached_modal_force_tpl(const Eigen::Matrix<S, 3, 3>& R_WB,
                                  const AttachmentShape<S>* phi_B,
                                  const Eigen::Matrix<S, 3, 1>& f_W,
                                  Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> Q_f) {
  if (phi_B == nullptr) return;
  const Eigen::Matrix<S, 3, 1> f_B = R_WB.transpose() * f_W;
  Q_f.noalias() += phi_B->transpose() * f_B;
}

}  // namespace flexref::core
