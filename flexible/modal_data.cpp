#include "flexible/modal_data.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

#include "rotation/so3.hpp"

namespace flexref::flexible {
namespace {

// Index 3a + b of the Cartesian pair (a, b) in ModalInvariants::phi_phi and x_phi.
constexpr std::size_t pair(int a, int b) {
  return static_cast<std::size_t>(detail::pair_index(a, b));
}
constexpr Eigen::Index pair_row(int a, int b) { return Eigen::Index{detail::pair_index(a, b)}; }

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("modal data: " + what);
}

std::string node_label(const ModalData& data, int k) {
  std::string label = "node " + std::to_string(k + 1);
  if (!data.node_names.empty())
    label += " ('" + data.node_names[static_cast<std::size_t>(k)] + "')";
  return label;
}

std::string mode_label(const ModalData& data, int i) {
  std::string label = "mode " + std::to_string(i + 1);
  if (!data.mode_names.empty())
    label += " ('" + data.mode_names[static_cast<std::size_t>(i)] + "')";
  return label;
}

std::string number_text(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

void check_sizes(const ModalData& data) {
  const Eigen::Index N = data.mass.size();
  const Eigen::Index n = data.phi.cols();
  if (N == 0) fail("no nodes (at least one node with a mass is required)");
  if (data.p_BoNode_B.cols() != N) {
    fail(std::to_string(N) + " nodal masses but " + std::to_string(data.p_BoNode_B.cols()) +
         " node positions");
  }
  if (data.phi.rows() != 3 * N) {
    fail("the mode-shape matrix has " + std::to_string(data.phi.rows()) + " rows, expected 3 × " +
         std::to_string(N) + " nodes = " + std::to_string(3 * N));
  }
  if (data.stiffness.size() != n) {
    fail(std::to_string(n) + " modes but " + std::to_string(data.stiffness.size()) +
         " modal stiffnesses");
  }
  if (data.damping_ratio.size() != n) {
    fail(std::to_string(n) + " modes but " + std::to_string(data.damping_ratio.size()) +
         " damping ratios (give zeros for an undamped body)");
  }
  if (!data.node_names.empty() && static_cast<Eigen::Index>(data.node_names.size()) != N) {
    fail(std::to_string(N) + " nodes but " + std::to_string(data.node_names.size()) +
         " node names (give none or one per node)");
  }
  if (!data.mode_names.empty() && static_cast<Eigen::Index>(data.mode_names.size()) != n) {
    fail(std::to_string(n) + " modes but " + std::to_string(data.mode_names.size()) +
         " mode names (give none or one per mode)");
  }
}

void check_nodes(const ModalData& data) {
  const int N = data.node_count();
  const int n = data.mode_count();
  for (int k = 0; k < N; ++k) {
    const double m = data.mass(k);
    if (!std::isfinite(m) || m <= 0.0) {
      fail(node_label(data, k) + " has mass " + number_text(m) + "; expected a finite mass > 0");
    }
    if (!data.p_BoNode_B.col(k).allFinite()) {
      fail(node_label(data, k) + " has a non-finite position");
    }
    for (int i = 0; i < n; ++i) {
      if (!data.mode_rows(k).col(i).allFinite()) {
        fail(mode_label(data, i) + " has a non-finite displacement at " + node_label(data, k));
      }
    }
  }
  std::unordered_set<std::string> names;
  for (int k = 0; k < static_cast<int>(data.node_names.size()); ++k) {
    const std::string& name = data.node_names[static_cast<std::size_t>(k)];
    if (name.empty()) fail("node " + std::to_string(k + 1) + " has an empty name");
    if (!names.insert(name).second) fail("duplicate node name '" + name + "'");
  }
}

void check_modes(const ModalData& data) {
  for (int i = 0; i < data.mode_count(); ++i) {
    const double K = data.stiffness(i);
    if (!std::isfinite(K) || K < 0.0) {
      fail(mode_label(data, i) + " has stiffness " + number_text(K) +
           "; expected a finite value ≥ 0");
    }
    const double zeta = data.damping_ratio(i);
    if (!std::isfinite(zeta) || zeta < 0.0) {
      fail(mode_label(data, i) + " has damping ratio " + number_text(zeta) +
           "; expected a finite value ≥ 0");
    }
  }
  const Eigen::MatrixXd m_ff = modal_mass_matrix(data);
  const int dependent = first_dependent_mode(m_ff);
  if (dependent >= 0) {
    if (m_ff(dependent, dependent) == 0.0) {
      fail(mode_label(data, dependent) + " has no displacement at any node (zero modal mass)");
    }
    fail("the modal mass matrix Σ m_k Φ_kᵀ Φ_k is not positive definite: " +
         mode_label(data, dependent) + " is (numerically) a linear combination of the modes " +
         "before it");
  }
}

}  // namespace

void ModalData::validate() const {
  check_sizes(*this);
  check_nodes(*this);
  check_modes(*this);
  if (geometric) geometric->validate(mode_count());
}

Eigen::MatrixXd modal_mass_matrix(const ModalData& data) {
  const int n = data.mode_count();
  Eigen::MatrixXd m_ff = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < data.node_count(); ++k) {
    const auto phi_k = data.mode_rows(k);
    m_ff.noalias() += data.mass(k) * phi_k.transpose() * phi_k;
  }
  // Symmetric up to the rounding of the products; make it exactly so.
  return 0.5 * (m_ff + m_ff.transpose());
}

int first_dependent_mode(const Eigen::MatrixXd& m_ff, double tolerance) {
  const Eigen::Index n = m_ff.rows();
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < i; ++j) {
      l(i, j) = (m_ff(i, j) - l.row(i).head(j).dot(l.row(j).head(j))) / l(j, j);
    }
    const double pivot = m_ff(i, i) - l.row(i).head(i).squaredNorm();
    if (!(pivot > tolerance * m_ff(i, i))) return static_cast<int>(i);
    l(i, i) = std::sqrt(pivot);
  }
  return -1;
}

Eigen::VectorXd natural_frequencies(const ModalData& data) {
  if (data.mode_count() == 0) return {};
  const Eigen::MatrixXd m_ff = modal_mass_matrix(data);
  const Eigen::MatrixXd K = data.stiffness.asDiagonal();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K, m_ff,
                                                                         Eigen::EigenvaluesOnly);
  if (solver.info() != Eigen::Success) fail("cannot compute the natural frequencies");
  // Eigenvalues of a positive semi-definite pencil may come out as −(rounding): clamp to 0.
  return solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

Eigen::VectorXd modal_damping(const ModalData& data) {
  const Eigen::MatrixXd m_ff = modal_mass_matrix(data);
  return 2.0 *
         data.damping_ratio.cwiseProduct(data.stiffness.cwiseProduct(m_ff.diagonal()).cwiseSqrt());
}

ModalInvariants make_modal_invariants(const ModalData& data) {
  data.validate();
  return modal_invariants_tpl<double>(data.mass, data.p_BoNode_B, data.phi,
                                      data.geometric ? &*data.geometric : nullptr);
}

namespace {

void check_q(const ModalInvariants& inv, const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  if (q_f.size() != inv.mode_count) {
    throw std::invalid_argument("modal invariants: q_f has " + std::to_string(q_f.size()) +
                                " entries, expected " + std::to_string(inv.mode_count));
  }
}

void check_q(const ModalData& data, const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  if (q_f.size() != data.mode_count()) {
    throw std::invalid_argument("modal data: q_f has " + std::to_string(q_f.size()) +
                                " entries, expected " + std::to_string(data.mode_count()));
  }
}

}  // namespace

Eigen::Vector3d first_moment(const ModalInvariants& inv,
                             const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  check_q(inv, q_f);
  return first_moment_tpl(inv, q_f);
}

Eigen::Vector3d first_moment_rate(const ModalInvariants& inv,
                                  const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                  const Eigen::Ref<const Eigen::VectorXd>& qd_f) {
  check_q(inv, q_f);
  check_q(inv, qd_f);
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (Eigen::Index j = 0; j < qd_f.size(); ++j) s += inv.S.col(j) * qd_f(j);
  if (inv.geometric) s += foreshortening_first_moment_rate(*inv.geometric, q_f, qd_f);
  return s;
}

Eigen::Matrix3d inertia_theta_theta(const ModalInvariants& inv,
                                    const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  check_q(inv, q_f);
  const Eigen::Index n = q_f.size();
  // L_ab = Σ m x_a Φ_b q
  Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      double sum = 0.0;
      for (Eigen::Index j = 0; j < n; ++j) sum += inv.x_phi(pair_row(a, b), j) * q_f(j);
      L(a, b) = sum;
    }
  }
  // Q_ab = qᵀ P_ab q (symmetric: Q_ba = Q_ab)
  Eigen::Matrix3d Q = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      const Eigen::MatrixXd& P = inv.phi_phi[pair(a, b)];
      double sum = 0.0;
      for (Eigen::Index j = 0; j < n; ++j) {
        double row = 0.0;
        for (Eigen::Index i = 0; i < n; ++i) row += q_f(i) * P(i, j);
        sum += row * q_f(j);
      }
      Q(a, b) = sum;
      Q(b, a) = sum;
    }
  }
  // J = Σ m ū ūᵀ, Ī_θθ = Σ m ũᵀũ = tr(J) I − J
  const Eigen::Matrix3d J = inv.J0 + L + L.transpose() + Q;
  Eigen::Matrix3d I = J.trace() * Eigen::Matrix3d::Identity() - J;
  if (inv.geometric) I += foreshortening_inertia(*inv.geometric, q_f);
  return I;
}

void inertia_theta_f(const ModalInvariants& inv, const Eigen::Ref<const Eigen::VectorXd>& q_f,
                     Eigen::Ref<Eigen::MatrixXd> out) {
  check_q(inv, q_f);
  const Eigen::Index n = q_f.size();
  if (out.rows() != 3 || out.cols() != n) {
    throw std::invalid_argument("inertia_theta_f: the output is " + std::to_string(out.rows()) +
                                "×" + std::to_string(out.cols()) + ", expected 3×" +
                                std::to_string(n));
  }
  for (int a = 0; a < 3; ++a) {
    const Eigen::MatrixXd& G = inv.phi_cross_phi[static_cast<std::size_t>(a)];
    for (Eigen::Index j = 0; j < n; ++j) {
      // row a of Σ m (Φq)~Φ: (qᵀ G_a)_j
      double sum = 0.0;
      for (Eigen::Index i = 0; i < n; ++i) sum += q_f(i) * G(i, j);
      out(a, j) = inv.I_theta_f0(a, j) + sum;
    }
  }
  if (!inv.geometric) return;
  // ΔĪ_θf row c = −(Z_c q_f)ᵀ (flexible/geometric_stiffness.hpp).
  for (const int c : inv.geometric->Z_nonzero) {
    const Eigen::MatrixXd& Z = inv.geometric->Z[static_cast<std::size_t>(c)];
    for (Eigen::Index j = 0; j < n; ++j) out(c, j) -= Z.col(j).dot(q_f);
  }
}

Eigen::Matrix3Xd inertia_theta_f(const ModalInvariants& inv,
                                 const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  Eigen::MatrixXd out(3, inv.mode_count);
  inertia_theta_f(inv, q_f, out);
  return out;
}

Eigen::Vector3d first_moment_direct(const ModalData& data,
                                    const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  check_q(data, q_f);
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (int k = 0; k < data.node_count(); ++k) {
    const Eigen::Vector3d u = data.p_BoNode_B.col(k) + data.mode_rows(k) * q_f;
    s += data.mass(k) * u;
  }
  return s;
}

Eigen::Matrix3d inertia_theta_theta_direct(const ModalData& data,
                                           const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  check_q(data, q_f);
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (int k = 0; k < data.node_count(); ++k) {
    const Eigen::Vector3d u = data.p_BoNode_B.col(k) + data.mode_rows(k) * q_f;
    const Eigen::Matrix3d u_hat = rotation::hat(u);
    I += data.mass(k) * u_hat.transpose() * u_hat;
  }
  return I;
}

Eigen::Matrix3Xd inertia_theta_f_direct(const ModalData& data,
                                        const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  check_q(data, q_f);
  Eigen::Matrix3Xd I = Eigen::Matrix3Xd::Zero(3, data.mode_count());
  for (int k = 0; k < data.node_count(); ++k) {
    const Eigen::Vector3d u = data.p_BoNode_B.col(k) + data.mode_rows(k) * q_f;
    I += data.mass(k) * rotation::hat(u) * data.mode_rows(k);
  }
  return I;
}

}  // namespace flexref::flexible
