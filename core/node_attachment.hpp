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
/// are core/attachment_tpl.hpp's, which the extended and quad model calls too.
///
/// *Decision* (docs/decisions.md): an attachment always sees the state's deformation, under the
/// LTE model too, where the other loads act on the undeformed body. A contact at a node exists
/// only through the deformation (a tube in a support whose frame does not move), so it must see
/// x_k + Φ_k q_f; the rigid rows then take the deformed arm, which is what the coupled model does.
#include <Eigen/Core>

#include "core/force_element.hpp"
#include "core/state.hpp"
#include "flexible/modal_data.hpp"

namespace flexref::core {

/// Where a body point deforms: the node index and its mode-shape rows Φ_k (3×n, body frame),
/// or node = −1 and no rows for a point of the rigid part.
struct NodeAttachment {
  int node = -1;
  Eigen::Matrix3Xd phi_B;  ///< Φ_k (3×n); empty for a hub point

  /// Node k of the modal data (copies Φ_k). Throws std::invalid_argument for a bad index.
  static NodeAttachment of_node(const flexible::ModalData& modal, int node);
  bool deforms() const { return node >= 0; }
  /// Φ_k q_f (body frame, m); zero for a hub point. Throws when the sizes differ.
  Eigen::Vector3d displacement_B(const BodyState& state) const;
  /// Φ_k q̇_f (body frame, m/s).
  Eigen::Vector3d displacement_rate_B(const BodyState& state) const;
};

/// World position of the attached point given by its undeformed position from the frame
/// origin: p_WBr + A (x_P − p_BoBr + Φ_k q_f).
Eigen::Vector3d attached_position_W(const BodyKinematics& body, const Eigen::Vector3d& p_BoP_B,
                                    const NodeAttachment& attachment);
/// Velocity of the material point at the world point P that moves with the attachment (P on a
/// sphere around the node, or the node itself): v_WBr + ω × (P − p_WBr) + A Φ_k q̇_f.
Eigen::Vector3d attached_velocity_W(const BodyKinematics& body, const Eigen::Vector3d& p_WP,
                                    const NodeAttachment& attachment);
/// Adds the force f_W applied at the world point P of the attachment to the body's wrench:
/// f, (P − p_WBr) × f and Φ_kᵀ Aᵀ f (see above). Allocates nothing.
void add_attached_force(const BodyKinematics& body, const NodeAttachment& attachment,
                        const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_WP, Wrench& wrench);

}  // namespace flexref::core
