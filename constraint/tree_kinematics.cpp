#include "constraint/tree_kinematics.hpp"

#include <algorithm>
#include <limits>

#include "rotation/euler_parameters.hpp"

namespace flexref::constraint {
TreeKinematics::TreeKinematics(SpanningTree tree, const std::vector<core::Body>& bodies)
    : tree_(std::move(tree)) {
  for (const core::Body& b : bodies) p_BoBr_B_.push_back(b.p_BoBr_B());
  columns_.resize(bodies.size());
  for (const Mobilizer& m : tree_.mobilizers) {
    std::vector<int>& columns = columns_[static_cast<std::size_t>(m.child)];
    if (m.parent != kGround) columns = columns_[static_cast<std::size_t>(m.parent)];
    for (int k = 0; k < constraint::velocity_count(m.kind); ++k) columns.push_back(m.u_offset + k);
    std::sort(columns.begin(), columns.end());
  }
}

TreeWorkspace TreeKinematics::make_workspace() const {
  const auto n = static_cast<std::size_t>(body_count());
  const int nu = velocity_count();
  TreeWorkspace ws;
  ws.state.resize(n);
  for (core::BodyState& s : ws.state) {
    s.q_f.resize(0);
    s.qd_f.resize(0);
  }
  ws.state.wear_depth.resize(0);
  ws.R_WB.assign(n, Eigen::Matrix3d::Identity());
  ws.w_WB_W.assign(n, Eigen::Vector3d::Zero());
  ws.alpha_bias_W.assign(n, Eigen::Vector3d::Zero());
  ws.a_bias_WBr.assign(n, Eigen::Vector3d::Zero());
  ws.relative.resize(tree_.mobilizers.size());
  const auto rows = static_cast<Eigen::Index>(3 * n);
  ws.Jw = Eigen::MatrixXd::Zero(rows, nu);
  ws.S = Eigen::MatrixXd::Zero(2 * rows, nu);
  ws.bias = Eigen::VectorXd::Zero(2 * rows);
  return ws;
}

void TreeKinematics::evaluate(const Vector& q, const Vector& u, TreeWorkspace& ws,
                              bool attitudes) const {
  evaluate_tree<true>(q, u, ws, attitudes);
}

void TreeKinematics::evaluate_state(const Vector& q, const Vector& u, TreeWorkspace& ws) const {
  evaluate_tree<false>(q, u, ws, true);
}

template <bool kJacobians>
void TreeKinematics::evaluate_tree(const Vector& q, const Vector& u, TreeWorkspace& ws,
                                   bool attitudes) const {
  for (std::size_t k = 0; k < tree_.mobilizers.size(); ++k) {
    const Mobilizer& m = tree_.mobilizers[k];
    RelativeMotion& rel = ws.relative[k];
    relative_motion(m, q.data() + m.q_offset, u.data() + m.u_offset, rel);
    const int nu_m = constraint::velocity_count(m.kind);
    const auto c = static_cast<std::size_t>(m.child);
    // The parent's pose, motion and bias (the ground's: identity, zero).
    const bool grounded = m.parent == kGround;
    const auto p = grounded ? c : static_cast<std::size_t>(m.parent);
    Eigen::Matrix3d R_WF = m.R_PF;
    Eigen::Vector3d p_WF = m.p_PrF_P, p_WPr = Eigen::Vector3d::Zero();
    Eigen::Vector3d v_P = Eigen::Vector3d::Zero(), w_P = Eigen::Vector3d::Zero();
    Eigen::Vector3d alpha_P = Eigen::Vector3d::Zero(), a_P = Eigen::Vector3d::Zero();
    if (!grounded) {
      const core::BodyState& sp = ws.state[p];
      R_WF.noalias() = ws.R_WB[p] * m.R_PF;
      p_WPr = sp.p_WBr;
      p_WF = p_WPr + ws.R_WB[p] * m.p_PrF_P;
      v_P = sp.v_WBr;
      w_P = ws.w_WB_W[p];
      alpha_P = ws.alpha_bias_W[p];
      a_P = ws.a_bias_WBr[p];
    }
    // Poses: R_WC = R_WF R_FM R_CMᵀ (products of the frames' matrices keep the exact zeros of
    // axis-aligned frames, which the closures' rank-revealing row choice relies on: a planar
    // loop's out-of-plane rows must come out exactly zero, not at rounding level).
    const Eigen::Matrix3d R_WC = R_WF * rel.R_FM * m.R_CM.transpose();
    core::BodyState& s = ws.state[c];
    if (m.kind == MobilizerKind::kFree || m.kind == MobilizerKind::kPivot) {
      // A root's attitude is its coordinates' (F = W, M = B): θ_WB as integrated.
      const int o = m.kind == MobilizerKind::kFree ? 3 : 0;
      s.theta_WB = q.segment<4>(m.q_offset + o);
    } else if (attitudes) {
      s.theta_WB = rotation::euler_parameters_from_matrix(R_WC);
    } else {
      s.theta_WB.setConstant(std::numeric_limits<double>::quiet_NaN());
    }
    const Eigen::Vector3d p_WM = p_WF + R_WF * rel.p_FM_F;
    const Eigen::Vector3d p_WCr = p_WM - R_WC * m.p_CrM_C;
    const Eigen::Vector3d r_PM = p_WM - p_WPr, r_MC = p_WCr - p_WM, r_PC = p_WCr - p_WPr;
    // Jacobians, column by column: ω_C = ω_P + R_WF H_w u; v_Cr = v_Pr + ω_P × r_PM + R_WF H_v u
    // + ω_C × r_MC, i.e. v_Pr's column less r_PC × ω_P's on the ancestors' columns (their H is
    // zero) and R_WF H_v − r_MC × R_WF H_w on the mobilizer's own. S stores v_WBr's rows (the
    // children's Jv) and ω̄'s = R_WCᵀ ω's; Jw keeps ω's in the world for the children.
    const Eigen::Index rc = 3 * static_cast<Eigen::Index>(c), rp = 3 * static_cast<Eigen::Index>(p);
    if constexpr (kJacobians) {
      for (const int col : columns_[c]) {
        Eigen::Map<Eigen::Vector3d> Jw_C(&ws.Jw(rc, col));
        Eigen::Map<Eigen::Vector3d> Jv_C(&ws.S(2 * rc, col));
        const int own = col - m.u_offset;
        if (own >= 0 && own < nu_m) {
          Jw_C.noalias() = R_WF * rel.H_w.col(own);
          Jv_C.noalias() = R_WF * rel.H_v.col(own);
          Jv_C -= r_MC.cross(Jw_C);
        } else {
          Jw_C = ws.Jw.block<3, 1>(rp, col);
          Jv_C = ws.S.block<3, 1>(2 * rp, col);
          Jv_C -= r_PC.cross(Jw_C);
        }
        ws.S.block<3, 1>(2 * rc + 3, col).noalias() = R_WC.transpose() * Jw_C;
      }
    }
    // Velocities and bias (the recursion of the header).
    Eigen::Vector3d w_rel_F = Eigen::Vector3d::Zero(), v_rel_F = Eigen::Vector3d::Zero();
    for (int j = 0; j < nu_m; ++j) {
      w_rel_F += rel.H_w.col(j) * u(m.u_offset + j);
      v_rel_F += rel.H_v.col(j) * u(m.u_offset + j);
    }
    const Eigen::Vector3d w_rel = R_WF * w_rel_F;
    const Eigen::Vector3d v_rel = R_WF * v_rel_F;
    const Eigen::Vector3d w_C = w_P + w_rel;
    ws.R_WB[c] = R_WC;
    ws.w_WB_W[c] = w_C;
    s.p_WBr = p_WCr;
    s.v_WBr = v_P + w_P.cross(r_PM) + v_rel + w_C.cross(r_MC);
    s.w_WB_B.noalias() = R_WC.transpose() * w_C;
    if constexpr (kJacobians) {
      const Eigen::Vector3d alpha_C = alpha_P + w_P.cross(w_rel) + R_WF * rel.w_dot_bias_F;
      const Eigen::Vector3d a_M = a_P + alpha_P.cross(r_PM) + w_P.cross(w_P.cross(r_PM)) +
                                  2.0 * w_P.cross(v_rel) + R_WF * rel.p_ddot_bias_F;
      const Eigen::Vector3d a_C = a_M + alpha_C.cross(r_MC) + w_C.cross(w_C.cross(r_MC));
      ws.alpha_bias_W[c] = alpha_C;
      ws.a_bias_WBr[c] = a_C;
      // The model's variables: (a_WBr, α̅ = R_WCᵀ ω̇) at u̇ = 0.
      ws.bias.segment<3>(2 * rc) = a_C;
      ws.bias.segment<3>(2 * rc + 3).noalias() = R_WC.transpose() * alpha_C;
    }
  }
}

void TreeKinematics::attitudes(TreeWorkspace& ws) const {
  for (const Mobilizer& m : tree_.mobilizers) {
    if (m.kind == MobilizerKind::kFree || m.kind == MobilizerKind::kPivot) continue;
    const auto c = static_cast<std::size_t>(m.child);
    ws.state[c].theta_WB = rotation::euler_parameters_from_matrix(ws.R_WB[c]);
  }
}

void TreeKinematics::coordinates(const core::State& state, Vector& q, Vector& u) const {
  q.resize(position_count());
  u.resize(velocity_count());
  for (const Mobilizer& m : tree_.mobilizers) {
    // The frames F and M in the world, and their velocities, from the bodies' states.
    Eigen::Matrix3d R_WP = Eigen::Matrix3d::Identity();
    Eigen::Vector3d p_WPr = Eigen::Vector3d::Zero(), v_WPr = Eigen::Vector3d::Zero();
    Eigen::Vector3d w_P = Eigen::Vector3d::Zero();
    if (m.parent != kGround) {
      const core::BodyState& sp = state[static_cast<std::size_t>(m.parent)];
      R_WP = rotation::rotation_matrix(sp.theta_WB);
      p_WPr = sp.p_WBr;
      v_WPr = sp.v_WBr;
      w_P = R_WP * sp.w_WB_B;
    }
    const core::BodyState& sc = state[static_cast<std::size_t>(m.child)];
    const Eigen::Matrix3d R_WC = rotation::rotation_matrix(sc.theta_WB);
    const Eigen::Vector3d w_C = R_WC * sc.w_WB_B;
    const Eigen::Matrix3d R_WF = R_WP * m.R_PF;
    const Eigen::Vector3d p_WF = p_WPr + R_WP * m.p_PrF_P;
    const Eigen::Vector3d p_WM = sc.p_WBr + R_WC * m.p_CrM_C;
    const Eigen::Vector3d v_WF = v_WPr + w_P.cross(p_WF - p_WPr);
    const Eigen::Vector3d v_WM = sc.v_WBr + w_C.cross(p_WM - sc.p_WBr);
    // p_FM = R_WFᵀ (p_WM − p_WF):  its rate in F is R_WFᵀ (v_WM − v_WF − ω_P × (p_WM − p_WF)).
    const Eigen::Matrix3d R_FM = R_WF.transpose() * R_WC * m.R_CM;
    const Eigen::Vector3d p_FM = R_WF.transpose() * (p_WM - p_WF);
    const Eigen::Vector3d p_dot_FM = R_WF.transpose() * (v_WM - v_WF - w_P.cross(p_WM - p_WF));
    const Eigen::Vector3d w_FM = R_WF.transpose() * (w_C - w_P);
    const bool root = m.kind == MobilizerKind::kFree || m.kind == MobilizerKind::kPivot;
    mobilizer_coordinates(m, R_FM, p_FM, w_FM, p_dot_FM, root ? &sc.theta_WB : nullptr,
                          q.data() + m.q_offset, u.data() + m.u_offset);
  }
}

void TreeKinematics::rates(const double* q, const double* u, double* q_dot) const {
  for (const Mobilizer& m : tree_.mobilizers) {
    coordinate_rates(m, q + m.q_offset, u + m.u_offset, q_dot + m.q_offset);
  }
}

void TreeKinematics::normalize(double* q) const {
  for (const Mobilizer& m : tree_.mobilizers) normalize_coordinates(m, q + m.q_offset);
}

void TreeKinematics::advance(const Vector& q, const Vector& u, double h, Vector& q_out) const {
  for (const Mobilizer& m : tree_.mobilizers) {
    advance_coordinates(m, q.data() + m.q_offset, u.data() + m.u_offset, h,
                        q_out.data() + m.q_offset);
  }
}

}  // namespace flexref::constraint
