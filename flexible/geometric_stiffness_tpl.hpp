#pragma once
/// \file geometric_stiffness_tpl.hpp
/// The evaluation of geometric stiffening (flexible/geometric_stiffness.hpp, docs/
/// geometric_stiffening.md GS-4 … GS-7) written once for any scalar type S: double (the
/// GeometricInvariants, GeometricProducts and ForeshorteningTerms every integrator uses) and the
/// extended and quad precisions of precision/ (Pinocchio's ModelTpl pattern). The double names
/// are aliases of these templates; precision/ instantiates the other scalars.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace flexref::flexible {

/// What the evaluations read: E_c, F_ab, Z_c = Σ_ab ε_cab F_ba (= Σ_k m_k (x_k × e_k)_c D_k),
/// and which of them are not identically zero (a straight beam along x has E_x, F_xb, Z_y, Z_z
/// only), so that a product with a zero matrix is skipped.
template <typename S>
struct GeometricInvariantsTpl {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  std::array<Matrix, 3> E;
  std::array<Matrix, 9> F;
  std::array<Matrix, 3> Z;
  std::vector<int> E_nonzero;  ///< indices c with E_c ≠ 0
  std::vector<int> F_nonzero;  ///< indices 3a+b with F_ab ≠ 0
  std::vector<int> Z_nonzero;  ///< indices c with Z_c ≠ 0
};

/// Products of the geometric matrices with the modal state, computed once per evaluation
/// (the only O(n²) work of the stiffening terms; zero columns for zero matrices).
template <typename S>
struct GeometricProductsTpl {
  Eigen::Matrix<S, Eigen::Dynamic, 9> F_q;   ///< column 3a+b: F_ab q_f
  Eigen::Matrix<S, Eigen::Dynamic, 3> E_q;   ///< column c: E_c q_f
  Eigen::Matrix<S, Eigen::Dynamic, 3> E_qd;  ///< column c: E_c q̇_f
  Eigen::Matrix<S, Eigen::Dynamic, 3> Z_q;   ///< column c: Z_c q_f
  Eigen::Matrix<S, Eigen::Dynamic, 3> Z_qd;  ///< column c: Z_c q̇_f
};

/// The second-order changes of the inertia quantities (body frame, about the invariants' origin;
/// GS-4 … GS-7), from the products of the same (q_f, q̇_f). O(n), allocation-free.
template <typename S>
struct ForeshorteningTermsTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  Vector3 ds = Vector3::Zero();     ///< Δs = Σ m_k w_k,      Δs_c = −½ q·E_c q
  Vector3 dS_qd = Vector3::Zero();  ///< ΔS q̇ = d(Δs)/dt,     −q̇·E_c q
  Vector3 ds_vv = Vector3::Zero();  ///< Σ m_k J̇_w,k q̇_f,     −q̇·E_c q̇
  Matrix3 dJ = Matrix3::Zero();     ///< ΔJ_ab = −½ q·(F_ab + F_ba) q
  Matrix3 dC = Matrix3::Zero();     ///< ΔC_ab = −q̇·F_ab q
  Vector3 z_vv = Vector3::Zero();   ///< z_c = q̇·Z_c q̇
};

template <typename S>
using VectorRef = Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>;

/// out.col(k) = M[k] x for every k in `nonzero` (symmetric M: its lower triangle is read); the
/// other columns are left as they are (zero when `out` was made zero). Allocates nothing.
template <typename S, std::size_t kCount, int kColumns>
void multiply_nonzero(const std::array<Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>, kCount>& M,
                      const std::vector<int>& nonzero, const std::type_identity_t<VectorRef<S>>& x,
                      Eigen::Matrix<S, Eigen::Dynamic, kColumns>& out) {
  for (const int k : nonzero) {
    out.col(k).noalias() =
        M[static_cast<std::size_t>(k)].template selfadjointView<Eigen::Lower>() * x;
  }
}

template <typename S>
GeometricProductsTpl<S> make_geometric_products_tpl(int mode_count) {
  const Eigen::Index n = mode_count;
  GeometricProductsTpl<S> p;
  p.F_q = Eigen::Matrix<S, Eigen::Dynamic, 9>::Zero(n, 9);
  p.E_q = Eigen::Matrix<S, Eigen::Dynamic, 3>::Zero(n, 3);
  p.E_qd = Eigen::Matrix<S, Eigen::Dynamic, 3>::Zero(n, 3);
  p.Z_q = Eigen::Matrix<S, Eigen::Dynamic, 3>::Zero(n, 3);
  p.Z_qd = Eigen::Matrix<S, Eigen::Dynamic, 3>::Zero(n, 3);
  return p;
}

/// O(n²), allocates nothing.
template <typename S>
void compute_geometric_products_tpl(const GeometricInvariantsTpl<S>& g, const VectorRef<S>& q_f,
                                    const VectorRef<S>& qd_f, GeometricProductsTpl<S>& p) {
  // Zero matrices leave their columns at zero (make_geometric_products, never written).
  multiply_nonzero<S>(g.F, g.F_nonzero, q_f, p.F_q);
  multiply_nonzero<S>(g.E, g.E_nonzero, q_f, p.E_q);
  multiply_nonzero<S>(g.E, g.E_nonzero, qd_f, p.E_qd);
  multiply_nonzero<S>(g.Z, g.Z_nonzero, q_f, p.Z_q);
  multiply_nonzero<S>(g.Z, g.Z_nonzero, qd_f, p.Z_qd);
}

/// Zero products (the LTE model's inertia at q_f = q̇_f = 0: no stiffening).
template <typename S>
void set_zero_geometric_products_tpl(GeometricProductsTpl<S>& p) {
  p.F_q.setZero();
  p.E_q.setZero();
  p.E_qd.setZero();
  p.Z_q.setZero();
  p.Z_qd.setZero();
}

/// GS-4 … GS-7 from the products.
template <typename S>
void foreshortening_terms_tpl(const VectorRef<S>& q_f, const VectorRef<S>& qd_f,
                              const GeometricProductsTpl<S>& p, ForeshorteningTermsTpl<S>& f) {
  const S half(0.5);
  for (int c = 0; c < 3; ++c) {
    f.ds(c) = -half * q_f.dot(p.E_q.col(c));  // GS-4
    f.dS_qd(c) = -qd_f.dot(p.E_q.col(c));     // GS-5
    f.ds_vv(c) = -qd_f.dot(p.E_qd.col(c));    // GS-6
    f.z_vv(c) = qd_f.dot(p.Z_qd.col(c));      // GS-7
  }
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      f.dC(a, b) = -qd_f.dot(p.F_q.col(3 * a + b));
      if (b < a) continue;
      f.dJ(a, b) = -half * (q_f.dot(p.F_q.col(3 * a + b)) + q_f.dot(p.F_q.col(3 * b + a)));
      f.dJ(b, a) = f.dJ(a, b);
    }
  }
}

/// out += ΔS(q_f)ᵀ v = −Σ_c v_c E_c q_f (a body force field's work on the foreshortening, GS-4).
/// Column by column: no temporary (gravity calls this in every evaluation).
template <typename S>
void add_foreshortening_first_moment_transpose_tpl(
    const GeometricInvariantsTpl<S>& g, const VectorRef<S>& q_f, const Eigen::Matrix<S, 3, 1>& v,
    Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> out) {
  for (const int c : g.E_nonzero) {
    const auto& E = g.E[static_cast<std::size_t>(c)];
    for (Eigen::Index j = 0; j < E.cols(); ++j) out.noalias() -= (v(c) * q_f(j)) * E.col(j);
  }
}

/// The invariants from matrices E_c, F_ab given in double (exact in S) about the frame origin,
/// moved in S to the point p (F_ab − p_b E_a, GS-2; none when p is zero), symmetrized and with
/// Z_c formed in S. `E` and `F` have been validated by the caller (GeometricStiffness::validate).
template <typename S>
GeometricInvariantsTpl<S> geometric_invariants_tpl(
    const std::array<Eigen::MatrixXd, 3>& E, const std::array<Eigen::MatrixXd, 9>& F,
    const Eigen::Matrix<S, 3, 1>& p = Eigen::Matrix<S, 3, 1>::Zero()) {
  GeometricInvariantsTpl<S> g;
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  for (int c = 0; c < 3; ++c) g.E[at(c)] = E[at(c)].template cast<S>();
  for (int ab = 0; ab < 9; ++ab) g.F[at(ab)] = F[at(ab)].template cast<S>();
  if (p(0) != S(0) || p(1) != S(0) || p(2) != S(0)) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) g.F[at(3 * a + b)] -= p(b) * g.E[at(a)];
    }
  }
  // Exactly symmetric (the products use the full matrices; symmetry makes the Lagrangian's
  // derivatives q ↦ F q the gradients of ½ q·F q).
  const S half(0.5);
  for (auto& M : g.E) M = (half * (M + M.transpose())).eval();
  for (auto& M : g.F) M = (half * (M + M.transpose())).eval();
  // Z_c = Σ_ab ε_cab F_ba: Z_x = F_zy − F_yz, Z_y = F_xz − F_zx, Z_z = F_yx − F_xy.
  for (int c = 0; c < 3; ++c) {
    const int a = (c + 1) % 3;
    const int b = (c + 2) % 3;
    g.Z[at(c)] = g.F[at(3 * b + a)] - g.F[at(3 * a + b)];
  }
  for (int c = 0; c < 3; ++c) {
    if (g.E[at(c)].cwiseAbs().maxCoeff() > S(0)) g.E_nonzero.push_back(c);
    if (g.Z[at(c)].cwiseAbs().maxCoeff() > S(0)) g.Z_nonzero.push_back(c);
  }
  for (int ab = 0; ab < 9; ++ab) {
    if (g.F[at(ab)].cwiseAbs().maxCoeff() > S(0)) g.F_nonzero.push_back(ab);
  }
  return g;
}

}  // namespace flexref::flexible
