/// \file flexible_dynamics.cpp
/// See flexible_dynamics.hpp for the formulas and their reductions to the invariants.
#include "flexible/flexible_dynamics.hpp"

#include <cstddef>
#include <stdexcept>
#include <string>

#include "flexible/inertia_terms.hpp"
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

// Σ_j x_j B.col(j) for a 3×n B (column axpys; Eigen's dynamic-inner-size GEMV may allocate).
Eigen::Vector3d times3(const Eigen::Matrix3Xd& B, const Eigen::VectorXd& x) {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (Eigen::Index j = 0; j < B.cols(); ++j) out += x(j) * B.col(j);
  return out;
}

}  // namespace

void flexible_mass_matrix(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                          const Eigen::VectorXd& q_f, Eigen::MatrixXd& M) {
  const Eigen::Index n = inv.mode_count;
  check_matrix("flexible_mass_matrix", n, q_f, M);
  InertiaTerms terms = make_inertia_terms(static_cast<int>(n));
  evaluate_inertia_terms(inv, R_WB, q_f, Eigen::Vector3d::Zero(), Eigen::VectorXd::Zero(n), terms);
  M.topLeftCorner<6, 6>() = terms.M_rr;
  M.topRightCorner(6, n) = terms.M_rf;
  M.bottomLeftCorner(n, 6) = terms.M_rf.transpose();
  M.bottomRightCorner(n, n) = inv.m_ff;
}

void flexible_quadratic_velocity(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                                 const Eigen::VectorXd& q_f, const Eigen::Vector3d& w_B,
                                 const Eigen::VectorXd& qd_f, Eigen::VectorXd& Qv) {
  const Eigen::Index n = inv.mode_count;
  check_sizes("flexible_quadratic_velocity", n, q_f, &qd_f, Qv.size());
  InertiaTerms terms = make_inertia_terms(static_cast<int>(n));
  evaluate_inertia_terms(inv, R_WB, q_f, w_B, qd_f, terms);
  Qv = terms.Qv;
}

double flexible_kinetic_energy(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                               const Eigen::VectorXd& q_f, const Eigen::Vector3d& v_W,
                               const Eigen::Vector3d& w_B, const Eigen::VectorXd& qd_f) {
  const Eigen::Index n = inv.mode_count;
  check_sizes("flexible_kinetic_energy", n, q_f, &qd_f, 6 + n);
  const Eigen::Vector3d v_B = R_WB.transpose() * v_W;  // Aᵀ Ṙ
  const Eigen::Vector3d s_t = first_moment(inv, q_f);
  const Eigen::Vector3d S_qd = first_moment_rate(inv, q_f, qd_f);
  const Eigen::Matrix3d I_tt = inertia_theta_theta(inv, q_f);
  // ω̄ᵀ Ī_θf q̇ = ω̄ᵀ I_θf0 q̇ + Σ_a ω̄_a qᵀ G_a q̇
  double w_Itf_qd = w_B.dot(times3(inv.I_theta_f0, qd_f));
  for (int a = 0; a < 3; ++a) {
    w_Itf_qd += w_B(a) * bilinear_form(inv.phi_cross_phi[idx(a)], q_f, qd_f);
  }
  if (inv.geometric) w_Itf_qd += w_B.dot(foreshortening_theta_f(*inv.geometric, q_f, qd_f));
  // vᵀMv = m|Ṙ|² + 2 Ṙᵀ(−A s̃_t ω̄) + 2 Ṙᵀ A S q̇ + ω̄ᵀĪ_θθω̄ + 2 ω̄ᵀĪ_θf q̇ + q̇ᵀ m_ff q̇
  const double vMv = inv.mass * v_W.squaredNorm() - 2.0 * v_B.dot(s_t.cross(w_B)) +
                     2.0 * v_B.dot(S_qd) + w_B.dot(I_tt * w_B) + 2.0 * w_Itf_qd +
                     bilinear_form(inv.m_ff, qd_f, qd_f);
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
