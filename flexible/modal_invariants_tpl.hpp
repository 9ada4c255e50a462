#pragma once
/// \file modal_invariants_tpl.hpp
/// The inertia invariants of a flexible body's nodes (Shabana's inertia shape integrals; see
/// flexible/modal_data.hpp) written once for any scalar type: double (ModalInvariants, which
/// every integrator uses) and the extended and quad precisions of precision/. The nodal data
/// (masses, positions, mode shapes) are double numbers, exact in any wider type; the sums are
/// formed in the scalar, so a quad model is the exact model of the same data.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <optional>

#include "flexible/compressed_block_tpl.hpp"
#include "flexible/geometric_stiffness.hpp"
#include "flexible/geometric_stiffness_tpl.hpp"

namespace flexref::flexible {

namespace detail {

/// (a, b, c) cyclic permutations of (0, 1, 2).
inline constexpr std::array<std::array<int, 3>, 3> kCyclicTriples = {
    {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}}};

/// Index 3a + b of the Cartesian pair (a, b) in phi_phi, x_phi and the products.
constexpr int pair_index(int a, int b) { return 3 * a + b; }

}  // namespace detail

/// Sums over the nodes k; a, b, c are Cartesian indices 0..2 of the body frame; Φ_k,a is row a of
/// Φ_k (1×n); ū_k = x_k + Φ_k q_f is the deformed position of node k (body frame, from the
/// origin the positions are measured from).
template <typename Scalar>
struct ModalInvariantsTpl {
  using Vector3 = Eigen::Matrix<Scalar, 3, 1>;
  using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;
  using Matrix3X = Eigen::Matrix<Scalar, 3, Eigen::Dynamic>;
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

  int mode_count = 0;
  Scalar mass = Scalar(0);       ///< m = Σ m_k
  Vector3 s0 = Vector3::Zero();  ///< s0 = Σ m_k x_k
  Matrix3 J0 = Matrix3::Zero();  ///< J0 = Σ m_k x_k x_kᵀ
  Matrix3 I0 = Matrix3::Zero();  ///< I0 = Σ m_k x̃_kᵀ x̃_k = tr(J0) I − J0
  Matrix3X S;                    ///< S = Σ m_k Φ_k (3×n)
  Matrix m_ff;                   ///< m_ff = Σ m_k Φ_kᵀ Φ_k (n×n), exactly symmetric
  Eigen::Matrix<Scalar, 9, Eigen::Dynamic> x_phi;  ///< row 3a+b: Σ m_k x_k,a Φ_k,b (9×n)
  std::array<Matrix, 9> phi_phi;  ///< [3a+b]: Σ m_k Φ_k,aᵀ Φ_k,b (n×n); [3a+a] exactly symmetric
  Matrix3X I_theta_f0;            ///< Σ m_k x̃_k Φ_k (3×n)
  /// [a] = phi_phi[3b+c] − phi_phi[3c+b] for (a, b, c) a cyclic permutation of (0, 1, 2):
  /// skew-symmetric, and row a of Σ m_k (Φ_k q)~ Φ_k is qᵀ phi_cross_phi[a].
  std::array<Matrix, 3> phi_cross_phi;
  /// [3a+b], a ≤ b: phi_phi[3a+b] on its nonzero rows and columns (compressed_block_tpl.hpp),
  /// what the modal products multiply with; empty for a > b (P_ba = P_abᵀ).
  std::array<CompressedBlockTpl<Scalar>, 9> phi_phi_blocks;
  /// Geometric stiffening's matrices about the same origin, when the data carry them.
  std::optional<GeometricInvariantsTpl<Scalar>> geometric;
};

/// The invariants of nodes with masses m_k, positions x_k − p (p_BoNode_B's columns, exact in
/// the scalar, moved to the point p there) and mode shapes Φ (3N×n), with the geometric stiffening
/// matrices about p when given. The caller has validated the data (ModalData::validate).
template <typename Scalar>
ModalInvariantsTpl<Scalar> modal_invariants_tpl(
    const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& p_BoNode_B, const Eigen::MatrixXd& phi,
    const GeometricStiffness* geometric,
    const Eigen::Matrix<Scalar, 3, 1>& p = Eigen::Matrix<Scalar, 3, 1>::Zero()) {
  using Inv = ModalInvariantsTpl<Scalar>;
  using Vector3 = typename Inv::Vector3;
  using Matrix = typename Inv::Matrix;
  const auto pair = [](int a, int b) { return static_cast<std::size_t>(detail::pair_index(a, b)); };
  const auto pair_row = [](int a, int b) { return Eigen::Index{detail::pair_index(a, b)}; };
  const auto n = static_cast<int>(phi.cols());
  Inv inv;
  inv.mode_count = n;
  inv.S = Inv::Matrix3X::Zero(3, n);
  inv.x_phi = Eigen::Matrix<Scalar, 9, Eigen::Dynamic>::Zero(9, n);
  for (Matrix& P : inv.phi_phi) P = Matrix::Zero(n, n);
  for (Eigen::Index k = 0; k < mass.size(); ++k) {
    const Scalar m(mass(k));
    const Vector3 x = p_BoNode_B.col(k).cast<Scalar>() - p;
    const Eigen::Matrix<Scalar, 3, Eigen::Dynamic> phi_k = phi.middleRows<3>(3 * k).cast<Scalar>();
    inv.mass += m;
    inv.s0 += m * x;
    inv.J0 += m * x * x.transpose();
    inv.S += m * phi_k;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        inv.x_phi.row(pair_row(a, b)) += (m * x(a)) * phi_k.row(b);
        // Only the upper triangle (a ≤ b) is summed; the lower one is its transpose.
        if (b >= a) {
          inv.phi_phi[pair(a, b)].noalias() += m * phi_k.row(a).transpose() * phi_k.row(b);
        }
      }
    }
  }
  const Scalar half(0.5);
  for (int a = 0; a < 3; ++a) {
    // P_aa is symmetric by definition; its summed triangles differ by rounding (m_k Φ_k,a is
    // rounded before the outer product). Symmetrized, m_ff = Σ_a P_aa is exactly symmetric.
    Matrix& P_aa = inv.phi_phi[pair(a, a)];
    P_aa = (half * (P_aa + P_aa.transpose())).eval();
    for (int b = 0; b < a; ++b) {
      inv.phi_phi[pair(a, b)] = inv.phi_phi[pair(b, a)].transpose();
    }
  }
  inv.J0 = half * (inv.J0 + inv.J0.transpose());
  inv.I0 = inv.J0.trace() * Inv::Matrix3::Identity() - inv.J0;
  inv.m_ff = inv.phi_phi[0] + inv.phi_phi[4] + inv.phi_phi[8];
  inv.I_theta_f0 = Inv::Matrix3X::Zero(3, n);
  for (const auto& [a, b, c] : detail::kCyclicTriples) {
    // (x̃ Φ)_a = x_b Φ_c − x_c Φ_b
    inv.I_theta_f0.row(a) = inv.x_phi.row(pair_row(b, c)) - inv.x_phi.row(pair_row(c, b));
    inv.phi_cross_phi[static_cast<std::size_t>(a)] =
        inv.phi_phi[pair(b, c)] - inv.phi_phi[pair(c, b)];
  }
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      inv.phi_phi_blocks[pair(a, b)] = compress_block_tpl<Scalar>(inv.phi_phi[pair(a, b)]);
    }
  }
  if (geometric != nullptr)
    inv.geometric = geometric_invariants_tpl<Scalar>(geometric->E, geometric->F, p);
  return inv;
}

/// Adds a rigid part (hub) of mass m, centre c and inertia I_c about its centre, all about the
/// invariants' origin: m, s0 += m c, J0 += tr(I_c)/2 I − I_c + m c cᵀ, I0 from J0.
template <typename Scalar>
void add_rigid_part_tpl(ModalInvariantsTpl<Scalar>& inv, const Scalar& mass,
                        const Eigen::Matrix<Scalar, 3, 1>& c,
                        const Eigen::Matrix<Scalar, 3, 3>& I_c) {
  using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;
  // The second moment Σ m x xᵀ of a body with inertia I about its centre: ½ tr(I) 1 − I.
  const Matrix3 J_c = (Scalar(0.5) * I_c.trace()) * Matrix3::Identity() - I_c;
  inv.mass += mass;
  inv.s0 += mass * c;
  inv.J0 += J_c + mass * c * c.transpose();
  inv.I0 = inv.J0.trace() * Matrix3::Identity() - inv.J0;
}

/// The first moment about the invariants' origin of the deformed body, s_t(q) = s0 + S q + Δs(q)
/// with Δs_c = −½ q·E_c q under geometric stiffening (GS-4): flexible::first_moment in double,
/// the precision model in S. By columns of S and E_c (no temporary). Allocates nothing.
template <typename Scalar>
Eigen::Matrix<Scalar, 3, 1> first_moment_tpl(
    const ModalInvariantsTpl<Scalar>& inv,
    const Eigen::Ref<const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>>& q) {
  Eigen::Matrix<Scalar, 3, 1> s = inv.s0;
  for (Eigen::Index j = 0; j < q.size(); ++j) s += inv.S.col(j) * q(j);
  if (inv.geometric) {
    for (const int c : inv.geometric->E_nonzero) {
      const auto& E = inv.geometric->E[static_cast<std::size_t>(c)];
      Scalar quadratic(0);
      for (Eigen::Index j = 0; j < q.size(); ++j) quadratic += q(j) * E.col(j).dot(q);
      s(c) += Scalar(-0.5) * quadratic;
    }
  }
  return s;
}

}  // namespace flexref::flexible
