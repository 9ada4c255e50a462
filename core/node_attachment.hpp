#pragma once
/// \file node_attachment.hpp
/// Loads and contacts at a deforming point of a flexible body (docs/modal_data.md, "Loads at
/// nodes"). A point attached to node k of a body's modal data moves with the node,
/// ū_P = x_P + Φ_k q_f (body frame, eq. 10), and translates without rotating relative to the
/// frame (the modal data carries no rotational mode shapes). A force f (world) applied at a
/// world point P of such an attachment enters the generalized forces by virtual work
/// δr_P = δp_WBr + δπ × (P − p_WBr) + A Φ_k δq_f:
///   Qe_R += f,   Qe_θ: τ_Br += (P − p_WBr) × f   (the deformed arm),   Qe_f += Φ_kᵀ Aᵀ f.
/// A point of the rigid part (hub, node = −1) has Φ = 0 and only the first two. The formulas
/// are core/attachment_tpl.hpp's; everything here is generic in the scalar type S, as the
/// force elements that use it (core/force_element.hpp).
///
/// *Decision* (docs/decisions.md): an attachment always sees the state's deformation, under the
/// LTE model too, where the other loads act on the undeformed body. A contact at a node exists
/// only through the deformation (a tube in a support whose frame does not move), so it must see
/// x_k + Φ_k q_f; the rigid rows then take the deformed arm, which is what the coupled model does.
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/attachment_tpl.hpp"
#include "core/force_element.hpp"
#include "core/state.hpp"
#include "flexible/modal_data.hpp"

namespace flexref::core {

/// Where a body point deforms: the node index and its mode-shape rows Φ_k (3×n, body frame),
/// or node = −1 and no rows for a point of the rigid part.
template <typename S>
struct NodeAttachmentTpl {
  int node = -1;
  AttachmentShape<S> phi_B;  ///< Φ_k (3×n); empty for a hub point

  NodeAttachmentTpl() = default;
  /// The same attachment in another scalar type (Φ_k's entries are exact in a wider type).
  template <typename U>
  explicit NodeAttachmentTpl(const NodeAttachmentTpl<U>& other)
      : node(other.node), phi_B(other.phi_B.template cast<S>()) {}

  /// Node k of the modal data (copies Φ_k). Throws std::invalid_argument for a bad index.
  static NodeAttachmentTpl of_node(const flexible::ModalData& modal, int node) {
    if (node < 0 || node >= modal.node_count()) {
      throw std::invalid_argument("node index " + std::to_string(node) + " outside 0.." +
                                  std::to_string(modal.node_count() - 1));
    }
    NodeAttachmentTpl a;
    a.node = node;
    a.phi_B = modal.mode_rows(node).template cast<S>();
    return a;
  }
  bool deforms() const { return node >= 0; }
  /// Φ_k of a deforming attachment (its size checked against q_f, n), nullptr for a hub point.
  /// Throws std::invalid_argument when the sizes differ.
  const AttachmentShape<S>* shape_for(Eigen::Index mode_count) const {
    if (!deforms()) return nullptr;
    if (phi_B.cols() != mode_count) {
      throw std::invalid_argument("node attachment has " + std::to_string(phi_B.cols()) +
                                  " modes, the body " + std::to_string(mode_count));
    }
    return &phi_B;
  }
};

using NodeAttachment = NodeAttachmentTpl<double>;

/// World position of the attached point given by its undeformed position from the frame
/// origin: p_WBr + A (x_P − p_BoBr + Φ_k q_f).
template <typename S>
Eigen::Matrix<S, 3, 1> attached_position_W(
    const BodyKinematicsTpl<S>& body, const std::type_identity_t<Eigen::Matrix<S, 3, 1>>& p_BoP_B,
    const NodeAttachmentTpl<S>& attachment) {
  const BodyStateTpl<S>& s = *body.state;
  return s.p_WBr + attached_offset_tpl<S>(body.R_WB, p_BoP_B - body.p_BoBr_B,
                                          attachment.shape_for(s.q_f.size()), s.q_f);
}

/// Velocity of the material point at the world point P that moves with the attachment (P on a
/// sphere around the node, or the node itself): v_WBr + ω × (P − p_WBr) + A Φ_k q̇_f.
template <typename S>
Eigen::Matrix<S, 3, 1> attached_velocity_W(const BodyKinematicsTpl<S>& body,
                                           const std::type_identity_t<Eigen::Matrix<S, 3, 1>>& p_WP,
                                           const NodeAttachmentTpl<S>& attachment) {
  const BodyStateTpl<S>& s = *body.state;
  return attached_velocity_tpl<S>(s.v_WBr, body.R_WB * s.w_WB_B, s.p_WBr, body.R_WB,
                                  attachment.shape_for(s.q_f.size()), s.qd_f, p_WP);
}

/// Adds the force f_W applied at the world point P of the attachment to the body's wrench:
/// f, (P − p_WBr) × f and Φ_kᵀ Aᵀ f (see above). Allocates nothing.
template <typename S>
void add_attached_force(const BodyKinematicsTpl<S>& body, const NodeAttachmentTpl<S>& attachment,
                        const std::type_identity_t<Eigen::Matrix<S, 3, 1>>& f_W,
                        const std::type_identity_t<Eigen::Matrix<S, 3, 1>>& p_WP,
                        WrenchTpl<S>& wrench) {
  wrench.add_force_at(f_W, p_WP - body.state->p_WBr);
  add_attached_modal_force_tpl<S>(body.R_WB, attachment.deforms() ? &attachment.phi_B : nullptr,
                                  f_W, wrench.Q_f);
}

}  // namespace flexref::core
