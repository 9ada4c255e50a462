#include "core/node_attachment.hpp"

#include <stdexcept>
#include <string>

namespace flexref::core {
namespace {

void require_modes(const NodeAttachment& a, const BodyState& s) {
  if (a.phi_B.cols() != s.q_f.size()) {
    throw std::invalid_argument("node attachment has " + std::to_string(a.phi_B.cols()) +
                                " modes, the body " + std::to_string(s.q_f.size()));
  }
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
  // p_WBr + A (x_P − p_BoBr + Φ_k q_f)
  return body.state->p_WBr +
         body.R_WB * (p_BoP_B - body.p_BoBr_B + attachment.displacement_B(*body.state));
}

Eigen::Vector3d attached_velocity_W(const BodyKinematics& body, const Eigen::Vector3d& p_WP,
                                    const NodeAttachment& attachment) {
  // v_WBr + ω × (P − p_WBr) + A Φ_k q̇_f
  const BodyState& s = *body.state;
  return s.v_WBr + (body.R_WB * s.w_WB_B).cross(p_WP - s.p_WBr) +
         body.R_WB * attachment.displacement_rate_B(s);
}

void add_attached_force(const BodyKinematics& body, const NodeAttachment& attachment,
                        const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_WP, Wrench& wrench) {
  wrench.add_force_at(f_W, p_WP - body.state->p_WBr);
  if (!attachment.deforms()) return;
  // Qe_f += Φ_kᵀ Aᵀ f
  const Eigen::Vector3d f_B = body.R_WB.transpose() * f_W;
  wrench.Q_f.noalias() += attachment.phi_B.transpose() * f_B;
}

}  // namespace flexref::core
