/// \file inertia_terms.cpp
/// See inertia_terms.hpp for the formulas.
#include "flexible/inertia_terms.hpp"

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "rotation/so3.hpp"

namespace flexref::flexible {
namespace {

// (a, b, c) cyclic permutations of (0, 1, 2).
constexpr std::array<std::array<int, 3>, 3> kCyclic = {{{0, 1, 2}, {1, 2, 0}, {2, 0, 1}}};

constexpr int pair(int a, int b) { return 3 * a + b; }
constexpr std::size_t at(int k) { return static_cast<std::size_t>(k); }

void check(const char* where, const ModalInvariants& inv, Eigen::Index q_size, Eigen::Index qd_size,
           const InertiaTerms& terms) {
  const Eigen::Index n = inv.mode_count;
  if (q_size != n || qd_size != n || terms.P_q.rows() != n || terms.Qv.size() != 6 + n) {
    throw std::invalid_argument(std::string(where) + ": q_f (" + std::to_string(q_size) +
                                "), q̇_f (" + std::to_string(qd_size) + ") and the terms (" +
                                std::to_string(terms.P_q.rows()) + " modes) must all have " +
                                std::to_string(n) + " modes");
  }
}

}  // namespace

InertiaTerms make_inertia_terms(int mode_count) {
  const Eigen::Index n = mode_count;
  InertiaTerms t;
  t.P_q = Eigen::Matrix<double, Eigen::Dynamic, 9>::Zero(n, 9);
  t.G_qd = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(n, 3);
  t.M_rr.setZero();
  t.M_rf = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, n);
  t.Qv = Eigen::VectorXd::Zero(6 + n);
  t.geometric_products = make_geometric_products(mode_count);
  return t;
}

void compute_modal_products(const ModalInvariants& inv,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& t) {
  check("compute_modal_products", inv, q_f.size(), qd_f.size(), t);
  if (inv.mode_count == 0) return;
  // Each stored P_ab (a ≤ b) is read for P_ab q and, off the diagonal, P_abᵀ q = P_ba q;
  // each G_a once. Matrix–vector products into contiguous columns: no temporaries.
  for (int a = 0; a < 3; ++a) {
    // P_aa is exactly symmetric (make_modal_invariants): its lower triangle suffices.
    t.P_q.col(pair(a, a)).noalias() =
        inv.phi_phi[at(pair(a, a))].selfadjointView<Eigen::Lower>() * q_f;
    for (int b = a + 1; b < 3; ++b) {
      const Eigen::MatrixXd& P = inv.phi_phi[at(pair(a, b))];
      t.P_q.col(pair(a, b)).noalias() = P * q_f;
      t.P_q.col(pair(b, a)).noalias() = P.transpose() * q_f;
    }
    t.G_qd.col(a).noalias() = inv.phi_cross_phi[at(a)] * qd_f;
  }
  t.X_q.noalias() = inv.x_phi * q_f;
  t.X_qd.noalias() = inv.x_phi * qd_f;
  t.S_q.noalias() = inv.S * q_f;
  t.S_qd.noalias() = inv.S * qd_f;
  if (inv.geometric) compute_geometric_products(*inv.geometric, q_f, qd_f, t.geometric_products);
}

void set_undeformed_products(InertiaTerms& t) {
  t.P_q.setZero();
  t.G_qd.setZero();
  t.X_q.setZero();
  t.X_qd.setZero();
  t.S_q.setZero();
  t.S_qd.setZero();
  set_zero_geometric_products(t.geometric_products);
}

void assemble_inertia_terms(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Vector3d& w_B,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& t) {
  check("assemble_inertia_terms", inv, q_f.size(), qd_f.size(), t);
  const Eigen::Index n = inv.mode_count;
  t.R_WB = R_WB;
  t.s_t = inv.s0 + t.S_q;
  // Geometric stiffening: Δs, ΔS q̇, ΔJ, ΔC enter every formula below through s_t, S q̇, J, C.
  const bool geometric = inv.geometric.has_value();
  t.constant_translation_coupling = !geometric;
  ForeshorteningTerms& fs = t.foreshortening;
  if (geometric) {
    foreshortening_terms(q_f, qd_f, t.geometric_products, fs);
    t.s_t += fs.ds;
  }
  const Eigen::Vector3d S_qd = geometric ? Eigen::Vector3d(t.S_qd + fs.dS_qd) : t.S_qd;

  // J = J0 + L + Lᵀ + Q (exactly symmetric: L_ab + L_ba and the symmetrized Q commute).
  Eigen::Matrix3d J;
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      const double L_sum = t.X_q(pair(a, b)) + t.X_q(pair(b, a));
      const double Q =
          a == b ? q_f.dot(t.P_q.col(pair(a, a)))
                 : 0.5 * (q_f.dot(t.P_q.col(pair(a, b))) + q_f.dot(t.P_q.col(pair(b, a))));
      J(a, b) = inv.J0(a, b) + L_sum + Q + (geometric ? fs.dJ(a, b) : 0.0);
      J(b, a) = J(a, b);
    }
  }
  t.I_tt = J.trace() * Eigen::Matrix3d::Identity() - J;

  // M_rr = [m I, −A s̃_t; s̃_t Aᵀ, Ī_θθ]
  t.M_rr.topLeftCorner<3, 3>() = inv.mass * Eigen::Matrix3d::Identity();
  t.M_rr.block<3, 3>(0, 3).noalias() = -R_WB * rotation::hat(t.s_t);
  t.M_rr.block<3, 3>(3, 0) = t.M_rr.block<3, 3>(0, 3).transpose();
  t.M_rr.block<3, 3>(3, 3) = t.I_tt;

  // M_rf = [A S; Ī_θf]: A S column by column, Ī_θf row a = Ī_θf0 row a + (u_cb − u_bc)ᵀ.
  if (n > 0) {
    t.M_rf.topRows<3>().noalias() = R_WB * inv.S;
    for (const auto& [a, b, c] : kCyclic) {
      t.M_rf.row(3 + a) =
          inv.I_theta_f0.row(a) + (t.P_q.col(pair(c, b)) - t.P_q.col(pair(b, c))).transpose();
    }
    if (geometric) {
      // [A ΔS; ΔĪ_θf] with rows −(E_c q)ᵀ and −(Z_c q)ᵀ (GS-5, GS-7).
      t.M_rf.topRows<3>().noalias() -= R_WB * t.geometric_products.E_q.transpose();
      t.M_rf.bottomRows<3>() -= t.geometric_products.Z_q.transpose();
    }
  }

  // Qv (see the header).
  const Eigen::Matrix3d W = rotation::hat(w_B);
  // W² = ω̄ω̄ᵀ − |ω̄|² I, exactly symmetric.
  const Eigen::Matrix3d W2 =
      w_B * w_B.transpose() - w_B.squaredNorm() * Eigen::Matrix3d::Identity();
  Eigen::Vector3d z_R = W2 * t.s_t + 2.0 * W * S_qd;
  if (geometric) z_R += fs.ds_vv;
  t.Qv.head<3>().noalias() = -R_WB * z_R;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) t.C(a, b) = t.X_qd(pair(b, a)) + qd_f.dot(t.P_q.col(pair(a, b)));
  }
  if (geometric) t.C += fs.dC;
  t.Qv.segment<3>(3) = -W * (t.I_tt * w_B) - 2.0 * (t.C.trace() * w_B - t.C * w_B);
  if (geometric) t.Qv.segment<3>(3) += fs.z_vv;
  if (n > 0) {
    // w9(3a+b) = (W²)_ab; Σ_ab (W²)_ab X_baᵀ = Xᵀ w9 since W² is symmetric.
    Eigen::Matrix<double, 9, 1> w9;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) w9(pair(a, b)) = W2(a, b);
    }
    auto Qv_f = t.Qv.tail(n);
    w9 = -w9;
    Qv_f.noalias() = inv.x_phi.transpose() * w9;
    Qv_f.noalias() += t.P_q * w9;
    Qv_f.noalias() += t.G_qd * (2.0 * w_B);
    // Σ_ab (W²)_ab F_ab q_f (w9 holds −W² here).
    if (geometric) Qv_f.noalias() -= t.geometric_products.F_q * w9;
  }
}

void evaluate_inertia_terms(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Vector3d& w_B,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& t) {
  compute_modal_products(inv, q_f, qd_f, t);
  assemble_inertia_terms(inv, R_WB, q_f, w_B, qd_f, t);
}

}  // namespace flexref::flexible
