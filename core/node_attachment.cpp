#include "core/node_attachment.hpp"

#include <stdexcept>
#include <string>

#include "core/attachment_tpl.hpp"

namespace flexref::core {
namespace {

void require_modes(const NodeAttachment& a, const BodyState& s) {
  if (a.phi_B.cols() != s.q_f.size()) {
    throw std::invalid_argument("node attachment has " + std::to_string(a.phi_B.cols()) +
                                " modes, the body " + std::to_string(s.q_f.size()));
  }
}

/// Φ_k of a deforming attachment (its size checked against the state), nullptr for a hub point.
const Eigen::Matrix3Xd* shape_of(const NodeAttachment& a, const BodyState& s) {
  if (!a.deforms()) return nullptr;
  require_modes(a, s);
  return &a.phi_B;
}

}  // namespace

NodeAttachment NodeAttachment::of_node(const flexible::ModalData& modal, int node) {
  if (node < 0 || node >= modal.node_count()) {
    throw std::invalid_argument("node index " + std::to_string(node) + " outside 0.." +
                                std::to_string(modal.node_count() - 1));
  }
  NodeAttachment a;
  a.node = node;
  a.phi_B = modal.mode_rows(node);
  return a;
}

Eigen::Vector3d NodeAttachment::displacement_B(const BodyState& state) const {
  if (!deforms()) return Eigen::Vector3d::Zero();
  require_modes(*this, state);
  return phi_B * state.q_f;
}

Eigen::Vector3d NodeAttachment::displacement_rate_B(const BodyState& state) const {
  if (!deforms()) return Eigen::Vector3d::Zero();
  require_modes(*this, state);
  return phi_B * state.qd_f;
}

Eigen::Vector3d attached_position_W(const BodyKinematics& body, const Eigen::Vector3d& p_BoP_B,
                                    const NodeAttachment& attachment) {
  const BodyState& s = *body.state;
  return s.p_WBr + attached_offset_tpl<double>(body.R_WB, p_BoP_B - body.p_BoBr_B,
                                               shape_of(attachment, s), s.q_f);
}

Eigen::Vector3d attached_velocity_W(const BodyKinematics& body, const Eigen::Vector3d& p_WP,
                                    const NodeAttachment& attachment) {
  const BodyState& s = *body.state;
  return attached_velocity_tpl<double>(s.v_WBr, body.R_WB * s.w_WB_B, s.p_WBr, body.R_WB,
                                       shape_of(attachment, s), s.qd_f, p_WP);
}

void add_attached_force(const BodyKinematics& body, const NodeAttachment& attachment,
                        const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_WP, Wrench& wrench) {
  wrench.add_force_at(f_W, p_WP - body.state->p_WBr);
  add_attached_modal_force_tpl<double>(
      body.R_WB, attachment.deforms() ? &attachment.phi_B : nullptr, f_W, wrench.Q_f);
}

}  // namespace flexref::core
