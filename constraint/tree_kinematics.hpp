#pragma once
/// \file tree_kinematics.hpp
/// Forward kinematics of a spanning tree (docs/reduced_coordinates.md, "Kinematics"): the
/// bodies' poses and velocities in the maximal model's variables from the joint coordinates
/// (q, u), the body-velocity Jacobian S(q) with v = S u, and the bias accelerations Ṡ u, so
/// that the bodies' accelerations are v̇ = S u̇ + Ṡ u. Here v stacks each body's (v_WBr, ω̄ =
/// w_WB_B), the rigid part of core::VelocityLayout, and v̇ its (a_WBr, α̅).
///
/// Recursion over the mobilizers, parents first (P the parent, C the child, F and M the
/// mobilizer's frames, X_FM = (R_FM, p_FM) its relative pose, w_rel = R_WF H_w u and
/// v_rel = R_WF H_v u its relative rates in the world; every vector in the world frame):
// clang-format off
///   R_WF = R_WP R_PF          p_WF = p_WPr + R_WP p_PrF
///   R_WM = R_WF R_FM          p_WM = p_WF + R_WF p_FM
///   R_WC = R_WM R_CMᵀ         p_WCr = p_WM − R_WC p_CrM
///   ω_C = ω_P + w_rel
///   v_Cr = v_Pr + ω_P × r_PM + v_rel + ω_C × r_MC,      r_PM = p_WM − p_WPr, r_MC = p_WCr − p_WM
///   (Ṡu)_ω,C = (Ṡu)_ω,P + ω_P × w_rel + R_WF Ḣ_w u
///   (Ṡu)_a,M = (Ṡu)_a,P + (Ṡu)_ω,P × r_PM + ω_P × (ω_P × r_PM) + 2 ω_P × v_rel + R_WF Ḣ_v u
///   (Ṡu)_a,C = (Ṡu)_a,M + (Ṡu)_ω,C × r_MC + ω_C × (ω_C × r_MC)
// clang-format on
/// (the second derivative of p_WM = p_WPr + r_PF + R_WF p_FM, Ṙ_WF = ω̃_P R_WF), and in the
/// model's variables ω̄ = R_WCᵀ ω_C, α̅ = R_WCᵀ ω̇_C (d(Rᵀω)/dt = Rᵀω̇ − Rᵀ ω̃ ω = Rᵀω̇).
/// S is stored dense, 6N × n_u, and swept on each body's ancestors' columns only (body_columns):
/// O(N d) per evaluation with d the tree's depth, what a tree of a few bodies and a handful of
/// loops needs; long chains want the articulated-body recursion instead.
#include <Eigen/Core>
#include <vector>

#include "constraint/spanning_tree.hpp"
#include "core/body.hpp"
#include "core/state.hpp"

namespace flexref::constraint {

/// Scratch and results of one forward-kinematics evaluation (sized once; never reallocated).
struct TreeWorkspace {
  /// The bodies' maximal state at (q, u): p_WBr, θ_WB, v_WBr, ω̄ (what core::Model evaluates).
  core::State state;
  std::vector<Eigen::Matrix3d> R_WB;
  std::vector<Eigen::Vector3d> w_WB_W;
  std::vector<Eigen::Vector3d> alpha_bias_W;  ///< (Ṡu)_ω per body, world
  std::vector<Eigen::Vector3d> a_bias_WBr;    ///< (Ṡu)_a per body, world
  std::vector<RelativeMotion> relative;       ///< per mobilizer
  Eigen::MatrixXd Jw;                         ///< 3N × n_u: ω_W = Jw u, body after body
  Eigen::MatrixXd S;                          ///< 6N × n_u: (v_WBr, ω̄) = S u, body after body
  Eigen::VectorXd bias;                       ///< 6N: (a_WBr, α̅) at u̇ = 0, i.e. Ṡ u
};

class TreeKinematics {
 public:
  using Vector = Eigen::VectorXd;

  TreeKinematics(SpanningTree tree, const std::vector<core::Body>& bodies);

  const SpanningTree& tree() const { return tree_; }
  int body_count() const { return static_cast<int>(p_BoBr_B_.size()); }
  int position_count() const { return tree_.position_count; }
  int velocity_count() const { return tree_.velocity_count; }
  TreeWorkspace make_workspace() const;

  /// Poses, velocities (ws.state), S and Ṡ u at (q, u). Without `attitudes`, the Euler
  /// parameters θ_WB of the bodies whose attitude the tree composes (all but free and pivot
  /// roots, whose θ are their coordinates) are left NaN: a caller that reads ws.R_WB alone saves
  /// their conversion from the matrix, and attitudes() sets them. Allocates nothing.
  void evaluate(const Vector& q, const Vector& u, TreeWorkspace& ws, bool attitudes = true) const;
  /// θ_WB from ws.R_WB where evaluate left them NaN: evaluate's own conversion, the same bits.
  void attitudes(TreeWorkspace& ws) const;
  /// The bodies' maximal state alone (ws.state, ws.R_WB, ws.w_WB_W), as evaluate forms it, to
  /// the same bits: an output's state, without S, Jw and the bias (left as they were).
  void evaluate_state(const Vector& q, const Vector& u, TreeWorkspace& ws) const;
  /// The joint coordinates of a maximal state that satisfies the tree's joints (the inverse of
  /// evaluate on its image; a violation of a tree joint's rows is dropped, not represented).
  void coordinates(const core::State& state, Vector& q, Vector& u) const;
  /// The columns of S body b's rows can be non-zero on: its mobilizer's and its ancestors' u,
  /// ascending. The sums over S's rows (M_r, Q_r, J_c) run over these alone.
  const std::vector<int>& body_columns(int b) const {
    return columns_[static_cast<std::size_t>(b)];
  }
  /// q̇ at (q, u), mobilizer by mobilizer (coordinate_rates). Allocates nothing.
  void rates(const double* q, const double* u, double* q_dot) const;
  /// Every mobilizer's Euler parameters scaled to unit norm. Allocates nothing.
  void normalize(double* q) const;
  /// q ⊕ h u, mobilizer by mobilizer (advance_coordinates). Allocates nothing.
  void advance(const Vector& q, const Vector& u, double h, Vector& q_out) const;

 private:
  /// evaluate's recursion; without kJacobians, the state alone (evaluate_state).
  template <bool kJacobians>
  void evaluate_tree(const Vector& q, const Vector& u, TreeWorkspace& ws, bool attitudes) const;

  SpanningTree tree_;
  std::vector<Eigen::Vector3d> p_BoBr_B_;
  std::vector<std::vector<int>> columns_;
};

}  // namespace flexref::constraint
