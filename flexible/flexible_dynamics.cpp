/// \file flexible_dynamics.cpp
/// See flexible_dynamics.hpp for the formulas and their reductions to the invariants.
#include "flexible/flexible_dynamics.hpp"

#include <cstddef>
#include <stdexcept>
#include <string>

#include "rotation/so3.hpp"

namespace flexref::flexible {
namespace {

std::size_t idx(int i) { return static_cast<std::size_t>(i); }

void check_sizes(const char* where, Eigen::Index n, const Eigen::VectorXd& q_f,
                 const Eigen::VectorXd* qd_f, Eigen::Index out_rows) {
  if (q_f.size() != n) {
    throw std::invalid_argument(std::string(where) + ": q_f has " + std::to_string(q_f.size()) +
                                " entries, expected " + std::to_string(n));
  }
  if (qd_f != nullptr && qd_f->size() != n) {
    throw std::invalid_argument(std::string(where) + ": qd_f has " + std::to_string(qd_f->size()) +
                                " entries, expected " + std::to_string(n));
  }
  if (out_rows != 6 + n) {
    throw std::invalid_argument(std::string(where) + ": the output has " +
                                std::to_string(out_rows) + " rows, expected " +
                                std::to_string(6 + n));
  }
}

void check_matrix(const char* where, Eigen::Index n, const Eigen::VectorXd& q_f,
                  const Eigen::MatrixXd& M) {
  check_sizes(where, n, q_f, nullptr, M.rows());
  if (M.cols() != 6 + n) {
    throw std::invalid_argument(std::string(where) + ": M is " + std::to_string(M.rows()) + "×" +
                                std::to_string(M.cols()) + ", expected " + std::to_string(6 + n) +
                                "×" + std::to_string(6 + n));
  }
}

// xᵀ P y by loops (no temporary).
double bilinear(const Eigen::VectorXd& x, const Eigen::MatrixXd& P, const Eigen::VectorXd& y) {
  double sum = 0.0;
  for (Eigen::Index j = 0; j < P.cols(); ++j) sum += y(j) * P.col(j).dot(x);
  return sum;
}

// out += alpha P x by column axpys (no temporary).
template <typename Out>
void add_matvec(double alpha, const Eigen::MatrixXd& P, const Eigen::VectorXd& x, Out&& out) {
  for (Eigen::Index j = 0; j < P.cols(); ++j) out += (alpha * x(j)) * P.col(j);
}

// Σ_j x_j B.col(j) for a 3×n B (column axpys; Eigen's dynamic-inner-size GEMV may allocate).
Eigen::Vector3d times3(const Eigen::Matrix3Xd& B, const Eigen::VectorXd& x) {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (Eigen::Index j = 0; j < B.cols(); ++j) out += x(j) * B.col(j);
  return out;
}

// Ī_θθ symmetrized (its two triangles are evaluated by different roundings).
Eigen::Matrix3d symmetric_inertia(const ModalInvariants& inv, const Eigen::VectorXd& q_f) {
  const Eigen::Matrix3d I = inertia_theta_theta(inv, q_f);
  return 0.5 * (I + I.transpose());
}

}  // namespace

void flexible_mass_matrix(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                          const Eigen::VectorXd& q_f, Eigen::MatrixXd& M) {
  const Eigen::Index n = inv.mode_count;
  check_matrix("flexible_mass_matrix", n, q_f, M);
  const Eigen::Vector3d s_t = first_moment(inv, q_f);
  M.topLeftCorner<3, 3>() = inv.mass * Eigen::Matrix3d::Identity();
  M.block<3, 3>(0, 3).noalias() = -R_WB * rotation::hat(s_t);
  M.block<3, 3>(3, 0) = M.block<3, 3>(0, 3).transpose();
  M.block<3, 3>(3, 3) = symmetric_inertia(inv, q_f);
  if (n == 0) return;
  for (Eigen::Index j = 0; j < n; ++j) M.block<3, 1>(0, 6 + j).noalias() = R_WB * inv.S.col(j);
  M.block(6, 0, n, 3) = M.block(0, 6, 3, n).transpose();
  inertia_theta_f(inv, q_f, M.block(3, 6, 3, n));
  M.block(6, 3, n, 3) = M.block(3, 6, 3, n).transpose();
  // m_ff is symmetric only to rounding (two triangles of a product): symmetrize.
  M.bottomRightCorner(n, n) = 0.5 * (inv.m_ff + inv.m_ff.transpose());
}

void flexible_quadratic_velocity(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                                 const Eigen::VectorXd& q_f, const Eigen::Vector3d& w_B,
                                 const Eigen::VectorXd& qd_f, Eigen::VectorXd& Qv) {
  const Eigen::Index n = inv.mode_count;
  check_sizes("flexible_quadratic_velocity", n, q_f, &qd_f, Qv.size());
  const Eigen::Matrix3d W = rotation::hat(w_B);
  const Eigen::Matrix3d W2 = W * W;
  const Eigen::Vector3d s_t = first_moment(inv, q_f);
  const Eigen::Vector3d S_qd = times3(inv.S, qd_f);
  Qv.head<3>().noalias() = -R_WB * (W2 * s_t + 2.0 * W * S_qd);

  // C_ab = Σ m (Φ q̇)_a ū_b = X_ba q̇ + qᵀ P_ba q̇;  Σ m ũ ω̄̃ Φ q̇ = tr(C) ω̄ − C ω̄.
  Eigen::Matrix3d C;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      C(a, b) =
          inv.x_phi.row(3 * b + a).dot(qd_f) + bilinear(q_f, inv.phi_phi[idx(3 * b + a)], qd_f);
    }
  }
  const Eigen::Matrix3d I_tt = symmetric_inertia(inv, q_f);
  Qv.segment<3>(3) = -W * (I_tt * w_B) - 2.0 * (C.trace() * w_B - C * w_B);

  // Qv_f = −Σ_ab (W²)_ab (X_baᵀ + P_ab q) + 2 Σ_a ω̄_a G_a q̇.
  auto Qf = Qv.tail(n);
  Qf.setZero();
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      Qf -= W2(a, b) * inv.x_phi.row(3 * b + a).transpose();
      add_matvec(-W2(a, b), inv.phi_phi[idx(3 * a + b)], q_f, Qf);
    }
    add_matvec(2.0 * w_B(a), inv.phi_cross_phi[idx(a)], qd_f, Qf);
  }
}

double flexible_kinetic_energy(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                               const Eigen::VectorXd& q_f, const Eigen::Vector3d& v_W,
                               const Eigen::Vector3d& w_B, const Eigen::VectorXd& qd_f) {
  const Eigen::Index n = inv.mode_count;
  check_sizes("flexible_kinetic_energy", n, q_f, &qd_f, 6 + n);
  const Eigen::Vector3d v_B = R_WB.transpose() * v_W;  // Aᵀ Ṙ
  const Eigen::Vector3d s_t = first_moment(inv, q_f);
  const Eigen::Vector3d S_qd = times3(inv.S, qd_f);
  const Eigen::Matrix3d I_tt = inertia_theta_theta(inv, q_f);
  // ω̄ᵀ Ī_θf q̇ = ω̄ᵀ I_θf0 q̇ + Σ_a ω̄_a qᵀ G_a q̇
  double w_Itf_qd = w_B.dot(times3(inv.I_theta_f0, qd_f));
  for (int a = 0; a < 3; ++a) {
    w_Itf_qd += w_B(a) * bilinear(q_f, inv.phi_cross_phi[idx(a)], qd_f);
  }
  // vᵀMv = m|Ṙ|² + 2 Ṙᵀ(−A s̃_t ω̄) + 2 Ṙᵀ A S q̇ + ω̄ᵀĪ_θθω̄ + 2 ω̄ᵀĪ_θf q̇ + q̇ᵀ m_ff q̇
  const double vMv = inv.mass * v_W.squaredNorm() - 2.0 * v_B.dot(s_t.cross(w_B)) +
                     2.0 * v_B.dot(S_qd) + w_B.dot(I_tt * w_B) + 2.0 * w_Itf_qd +
                     bilinear(qd_f, inv.m_ff, qd_f);
  return 0.5 * vMv;
}

void flexible_mass_matrix_by_nodes(const ModalData& data, const Eigen::Matrix3d& R_WB,
                                   const Eigen::VectorXd& q_f, Eigen::MatrixXd& M) {
  const Eigen::Index n = data.mode_count();
  check_matrix("flexible_mass_matrix_by_nodes", n, q_f, M);
  M.setZero();
  Eigen::MatrixXd L(3, 6 + n);
  for (int k = 0; k < data.node_count(); ++k) {
    const auto Phi = data.mode_rows(k);
    const Eigen::Vector3d u = data.p_BoNode_B.col(k) + Phi * q_f;
    L.leftCols<3>().setIdentity();
    L.middleCols<3>(3) = -R_WB * rotation::hat(u);
    L.rightCols(n) = R_WB * Phi;
    M.noalias() += data.mass(k) * L.transpose() * L;
  }
}

void flexible_quadratic_velocity_by_nodes(const ModalData& data, const Eigen::Matrix3d& R_WB,
                                          const Eigen::VectorXd& q_f, const Eigen::Vector3d& w_B,
                                          const Eigen::VectorXd& qd_f, Eigen::VectorXd& Qv) {
  const Eigen::Index n = data.mode_count();
  check_sizes("flexible_quadratic_velocity_by_nodes", n, q_f, &qd_f, Qv.size());
  Qv.setZero();
  Eigen::MatrixXd L(3, 6 + n);
  for (int k = 0; k < data.node_count(); ++k) {
    const auto Phi = data.mode_rows(k);
    const Eigen::Vector3d u = data.p_BoNode_B.col(k) + Phi * q_f;
    const Eigen::Vector3d v = Phi * qd_f;
    L.leftCols<3>().setIdentity();
    L.middleCols<3>(3) = -R_WB * rotation::hat(u);
    L.rightCols(n) = R_WB * Phi;
    // velocity-dependent part of r̈_k (eq. 17)
    const Eigen::Vector3d a_v = R_WB * (w_B.cross(w_B.cross(u)) + 2.0 * w_B.cross(v));
    Qv.noalias() -= data.mass(k) * L.transpose() * a_v;
  }
}

double flexible_kinetic_energy_by_nodes(const ModalData& data, const Eigen::Matrix3d& R_WB,
                                        const Eigen::VectorXd& q_f, const Eigen::Vector3d& v_W,
                                        const Eigen::Vector3d& w_B, const Eigen::VectorXd& qd_f) {
  const Eigen::Index n = data.mode_count();
  check_sizes("flexible_kinetic_energy_by_nodes", n, q_f, &qd_f, 6 + n);
  double T = 0.0;
  for (int k = 0; k < data.node_count(); ++k) {
    const auto Phi = data.mode_rows(k);
    const Eigen::Vector3d u = data.p_BoNode_B.col(k) + Phi * q_f;
    const Eigen::Vector3d r_dot = v_W + R_WB * (w_B.cross(u) + Phi * qd_f);
    T += 0.5 * data.mass(k) * r_dot.squaredNorm();
  }
  return T;
}

}  // namespace flexref::flexible
