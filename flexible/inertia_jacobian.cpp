/// \file inertia_jacobian.cpp
/// See inertia_jacobian.hpp for the formulas.
#include "flexible/inertia_jacobian.hpp"

#include <cstddef>
#include <stdexcept>
#include <string>

#include "rotation/so3.hpp"

namespace flexref::flexible {
namespace {

constexpr int pair_entry(int a, int b) { return 3 * a + b; }
constexpr std::size_t index_at(int k) { return static_cast<std::size_t>(k); }

// 3×3 matrix from nine entries m(3a+b) (a row of an n×9 product block).
Eigen::Matrix3d matrix_of(const Eigen::Matrix<double, 1, 9>& m) {
  Eigen::Matrix3d out;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) out(a, b) = m(pair_entry(a, b));
  }
  return out;
}

// tr(X) u − X u
Eigen::Vector3d trace_minus(const Eigen::Matrix3d& X, const Eigen::Vector3d& u) {
  return X.trace() * u - X * u;
}

// The geometric-stiffening blocks of the header (coupled model), added to `out`.
// W = ω̄̃, W2 = W², b = Aᵀ a and b̃ as the caller formed them.
void add_geometric_jacobian(const GeometricInvariants& g, const InertiaTerms& t,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f,
                            const Eigen::Vector3d& w_B, const Eigen::Matrix3d& W,
                            const Eigen::Matrix3d& W2, const Eigen::Vector3d& b,
                            const Eigen::Matrix3d& b_hat, const Eigen::Vector3d& alpha,
                            const Eigen::Ref<const Eigen::VectorXd>& qdd, InertiaJacobianScratch& s,
                            Eigen::Ref<Eigen::MatrixXd> out) {
  const Eigen::Index n = qd_f.size();
  const GeometricProducts& p = t.geometric_products;
  const ForeshorteningTerms& f = t.foreshortening;
  const Eigen::Matrix3d& A = t.R_WB;
  multiply_nonzero<double>(g.F, g.F_nonzero, qd_f, s.F_qd);
  multiply_nonzero<double>(g.E, g.E_nonzero, qdd, s.E_qdd);
  multiply_nonzero<double>(g.Z, g.Z_nonzero, qdd, s.Z_qdd);
  Eigen::Vector3d sigma_qdd;  // ΔS q̈_f
  for (int c = 0; c < 3; ++c) sigma_qdd(c) = -qdd.dot(p.E_q.col(c));

  // π̄ columns.
  out.block<3, 3>(0, kJacobianRotation).noalias() -=
      A * rotation::hat(2.0 * W * f.dS_qd + sigma_qdd + f.ds_vv);
  out.block(6, kJacobianRotation, n, 3).noalias() -= p.E_q * b_hat;

  // ω̄ columns.
  out.block<3, 3>(0, kJacobianAngularVelocity).noalias() -= 2.0 * A * rotation::hat(f.dS_qd);
  for (int c = 0; c < 3; ++c) {
    auto col = out.block(6, kJacobianAngularVelocity + c, n, 1);
    for (int k = 0; k < 3; ++k) {
      col.noalias() -= w_B(k) * (p.F_q.col(pair_entry(c, k)) + p.F_q.col(pair_entry(k, c)));
      col.noalias() += (2.0 * w_B(c)) * p.F_q.col(pair_entry(k, k));
    }
  }

  auto dq = out.middleCols(kJacobianModes, n);
  auto dqd = out.middleCols(kJacobianModes + n, n);
  const Eigen::Matrix3d alpha_W2 = rotation::hat(alpha) + W2;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector3d EQ = p.E_q.row(j).transpose();
    const Eigen::Vector3d EQd = p.E_qd.row(j).transpose();
    const Eigen::Vector3d EQdd = s.E_qdd.row(j).transpose();
    // Translation rows.
    dq.col(j).head<3>().noalias() -= A * (alpha_W2 * EQ + EQdd + 2.0 * W * EQd);
    dqd.col(j).head<3>().noalias() -= 2.0 * A * (W * EQ + EQd);
    // Rotation rows.
    const Eigen::Matrix3d F = matrix_of(p.F_q.row(j));
    const Eigen::Matrix3d dJ = -(F + F.transpose());
    const Eigen::Matrix3d dC = -matrix_of(s.F_qd.row(j));
    dq.col(j).segment<3>(3) += b_hat * EQ + trace_minus(dJ, alpha) - W * (dJ * w_B) -
                               s.Z_qdd.row(j).transpose() + 2.0 * trace_minus(dC, w_B);
    dqd.col(j).segment<3>(3) += 2.0 * trace_minus(-F, w_B) - 2.0 * p.Z_qd.row(j).transpose();
  }
  // Modal rows.
  for (const int c : g.E_nonzero) dq.bottomRows(n).noalias() -= b(c) * g.E[index_at(c)];
  for (const int c : g.Z_nonzero) dq.bottomRows(n).noalias() -= alpha(c) * g.Z[index_at(c)];
  for (const int ab : g.F_nonzero)
    dq.bottomRows(n).noalias() -= W2(ab / 3, ab % 3) * g.F[index_at(ab)];
}

}  // namespace

InertiaJacobianScratch make_inertia_jacobian_scratch(int mode_count) {
  const Eigen::Index n = mode_count;
  InertiaJacobianScratch s;
  s.P_qd = Eigen::Matrix<double, Eigen::Dynamic, 9>::Zero(n, 9);
  s.G_qdd = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(n, 3);
  s.dJ = Eigen::Matrix<double, Eigen::Dynamic, 9>::Zero(n, 9);
  s.dC = Eigen::Matrix<double, Eigen::Dynamic, 9>::Zero(n, 9);
  s.F_qd = Eigen::Matrix<double, Eigen::Dynamic, 9>::Zero(n, 9);
  s.E_qdd = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(n, 3);
  s.Z_qdd = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(n, 3);
  return s;
}

void inertia_residual_jacobian(const ModalInvariants& inv, const InertiaTerms& t, bool coupled,
                               const Eigen::Ref<const Eigen::VectorXd>& q_f,
                               const Eigen::Vector3d& w_B,
                               const Eigen::Ref<const Eigen::VectorXd>& qd_f,
                               const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::VectorXd& K,
                               const Eigen::VectorXd& D, InertiaJacobianScratch& s,
                               Eigen::Ref<Eigen::MatrixXd> out) {
  const Eigen::Index n = inv.mode_count;
  if (q_f.size() != n || qd_f.size() != n || x.size() != 6 + n || K.size() != n || D.size() != n ||
      t.mode_count() != n || s.P_qd.rows() != n || out.rows() != 6 + n || out.cols() != 6 + 2 * n) {
    throw std::invalid_argument("inertia_residual_jacobian: sizes do not match " +
                                std::to_string(n) + " modes");
  }
  const Eigen::Matrix3d& A = t.R_WB;
  const Eigen::Vector3d a = x.head<3>();
  const Eigen::Vector3d alpha = x.segment<3>(3);
  const auto qdd = x.tail(n);
  const Eigen::Vector3d b = A.transpose() * a;  // Aᵀ a
  const Eigen::Matrix3d W = rotation::hat(w_B);
  const Eigen::Matrix3d W2 =
      w_B * w_B.transpose() - w_B.squaredNorm() * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d b_hat = rotation::hat(b);
  out.setZero();

  // π̄ columns.
  Eigen::Vector3d z_R = alpha.cross(t.s_t) + W2 * t.s_t + 2.0 * W * t.S_qd;
  if (coupled && n > 0) z_R.noalias() += inv.S * qdd;
  out.block<3, 3>(0, kJacobianRotation).noalias() = -A * rotation::hat(z_R);
  out.block<3, 3>(3, kJacobianRotation).noalias() = rotation::hat(t.s_t) * b_hat;
  if (n > 0) out.block(6, kJacobianRotation, n, 3).noalias() = inv.S.transpose() * b_hat;

  // ω̄ columns.
  out.block<3, 3>(0, kJacobianAngularVelocity).noalias() =
      A *
      (-rotation::hat(w_B.cross(t.s_t)) - W * rotation::hat(t.s_t) - 2.0 * rotation::hat(t.S_qd));
  out.block<3, 3>(3, kJacobianAngularVelocity) =
      -rotation::hat(t.I_tt * w_B) + W * t.I_tt +
      2.0 * (t.C.trace() * Eigen::Matrix3d::Identity() - t.C);
  if (n == 0) return;
  // ∂R_f/∂ω̄_c with Y_ab = X_baᵀ + u_ab: Σ_b ω̄_b Y_cb + Σ_a ω̄_a Y_ac − 2 ω̄_c Σ_a Y_aa − 2 g_c.
  for (int c = 0; c < 3; ++c) {
    auto col = out.block(6, kJacobianAngularVelocity + c, n, 1);
    for (int k = 0; k < 3; ++k) {
      // Y_ck and Y_kc, each weighted by ω̄_k; Y_kk by −2 ω̄_c.
      col.noalias() +=
          w_B(k) * (inv.x_phi.row(pair_entry(k, c)).transpose() + t.P_q.col(pair_entry(c, k)) +
                    inv.x_phi.row(pair_entry(c, k)).transpose() + t.P_q.col(pair_entry(k, c)));
      col.noalias() -= (2.0 * w_B(c)) *
                       (inv.x_phi.row(pair_entry(k, k)).transpose() + t.P_q.col(pair_entry(k, k)));
    }
    col.noalias() -= 2.0 * t.G_qd.col(c);
  }

  auto dq = out.middleCols(kJacobianModes, n);
  auto dqd = out.middleCols(kJacobianModes + n, n);
  // ∂R_f/∂q_f ∋ K, ∂R_f/∂q̇_f ∋ D in both models.
  dq.bottomRows(n).diagonal() = K;
  dqd.bottomRows(n).diagonal() = D;
  if (!coupled) return;

  // Extra products: P_ab q̇_f, G_a q̈_f.
  for (int k = 0; k < 9; ++k) s.P_qd.col(k).noalias() = inv.phi_phi[index_at(k)] * qd_f;
  for (int k = 0; k < 3; ++k) s.G_qdd.col(k).noalias() = inv.phi_cross_phi[index_at(k)] * qdd;

  // q_f columns. Translation rows: A (α̅̃ + W²) S.
  dq.topRows<3>().noalias() = (A * (rotation::hat(alpha) + W2)) * inv.S;
  // Rotation rows: −b̃ S_j + tr(dJ_j) α̅ − dJ_j α̅ − W dJ_j ω̄ + (G_a q̈)_j + 2 (tr(dC_j) ω̄ − dC_j ω̄).
  for (int p = 0; p < 3; ++p) {
    for (int r = 0; r < 3; ++r) {
      s.dJ.col(pair_entry(p, r)) = inv.x_phi.row(pair_entry(p, r)).transpose() +
                                   inv.x_phi.row(pair_entry(r, p)).transpose() +
                                   t.P_q.col(pair_entry(p, r)) + t.P_q.col(pair_entry(r, p));
      s.dC.col(pair_entry(p, r)) = s.P_qd.col(pair_entry(r, p));  // dC_pr = P_rp q̇
    }
  }
  dq.middleRows<3>(3).noalias() = (-b_hat) * inv.S;
  for (int p = 0; p < 3; ++p) {
    auto row = dq.row(3 + p);
    // tr(dJ) α̅_p − Σ_r dJ_pr α̅_r − Σ_c W_pc Σ_r dJ_cr ω̄_r
    for (int c = 0; c < 3; ++c) row.noalias() += alpha(p) * s.dJ.col(pair_entry(c, c)).transpose();
    for (int r = 0; r < 3; ++r) {
      row.noalias() -= alpha(r) * s.dJ.col(pair_entry(p, r)).transpose();
      for (int c = 0; c < 3; ++c) {
        row.noalias() -= (W(p, c) * w_B(r)) * s.dJ.col(pair_entry(c, r)).transpose();
      }
    }
    row.noalias() += s.G_qdd.col(p).transpose();
    // 2 (tr(dC) ω̄_p − Σ_r dC_pr ω̄_r)
    for (int c = 0; c < 3; ++c)
      row.noalias() += (2.0 * w_B(p)) * s.dC.col(pair_entry(c, c)).transpose();
    for (int r = 0; r < 3; ++r)
      row.noalias() -= (2.0 * w_B(r)) * s.dC.col(pair_entry(p, r)).transpose();
  }
  // Modal rows: + Σ_ab (W²)_ab P_ab − Σ_a α̅_a G_a.
  for (int p = 0; p < 3; ++p) {
    for (int r = 0; r < 3; ++r)
      dq.bottomRows(n).noalias() += W2(p, r) * inv.phi_phi[index_at(pair_entry(p, r))];
    dq.bottomRows(n).noalias() -= alpha(p) * inv.phi_cross_phi[index_at(p)];
  }

  // q̇_f columns. Translation rows: 2 A W S; rotation rows: 2 (tr(dC') ω̄ − dC' ω̄) with
  // dC'_pr = X_rp + u_pr; modal rows: − 2 Σ_a ω̄_a G_a.
  dqd.topRows<3>().noalias() = (2.0 * A * W) * inv.S;
  for (int p = 0; p < 3; ++p) {
    for (int r = 0; r < 3; ++r) {
      s.dC.col(pair_entry(p, r)) =
          inv.x_phi.row(pair_entry(r, p)).transpose() + t.P_q.col(pair_entry(p, r));
    }
  }
  for (int p = 0; p < 3; ++p) {
    auto row = dqd.row(3 + p);
    for (int c = 0; c < 3; ++c)
      row.noalias() += (2.0 * w_B(p)) * s.dC.col(pair_entry(c, c)).transpose();
    for (int r = 0; r < 3; ++r)
      row.noalias() -= (2.0 * w_B(r)) * s.dC.col(pair_entry(p, r)).transpose();
  }
  for (int p = 0; p < 3; ++p) {
    dqd.bottomRows(n).noalias() -= (2.0 * w_B(p)) * inv.phi_cross_phi[index_at(p)];
  }
  if (inv.geometric) {
    add_geometric_jacobian(*inv.geometric, t, qd_f, w_B, W, W2, b, b_hat, alpha, qdd, s, out);
  }
}

}  // namespace flexref::flexible
