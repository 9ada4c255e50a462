#pragma once
/// \file small_cholesky.hpp
/// Cholesky factorization A = L Lᵀ and its triangular solves for the small dense symmetric
/// positive definite matrices of the reduced form (constraint/reduced_model.hpp: M_r, n_u × n_u,
/// and the closures' Schur complement, r × r), in plain loops over the columns of a column-major
/// Eigen::MatrixXd. At these sizes (a handful to a few tens) Eigen's dynamic-size LLT,
/// triangular solves and products spend more in their blocking and dispatch than in the
/// arithmetic (docs/performance.md, "Reduced coordinates"); the loops are the textbook
/// column-oriented ones (Golub & Van Loan, "Matrix computations", 4th ed., Alg. 4.2.2 and
/// 3.1.3-3.1.4), O(n³/6) and O(n²), allocating nothing.
#include <Eigen/Core>
#include <cmath>

namespace flexref::constraint {

/// A = L Lᵀ in place: L overwrites A's lower triangle (the strict upper triangle is neither read
/// nor written). Returns −1, or the first column j whose pivot A(j,j) − Σ L(j,k)² is not
/// positive (or NaN): A is not positive definite and L is complete only left of j.
inline Eigen::Index cholesky_in_place(Eigen::MatrixXd& A) {
  const Eigen::Index n = A.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    double* a_j = A.col(j).data();
    for (Eigen::Index k = 0; k < j; ++k) {
      const double l_jk = A(j, k);
      const double* l_k = A.col(k).data();
      for (Eigen::Index i = j; i < n; ++i) a_j[i] -= l_jk * l_k[i];
    }
    if (!(a_j[j] > 0.0)) return j;
    const double l_jj = std::sqrt(a_j[j]);
    a_j[j] = l_jj;
    const double inverse = 1.0 / l_jj;
    for (Eigen::Index i = j + 1; i < n; ++i) a_j[i] *= inverse;
  }
  return -1;
}

/// x ← L⁻¹ x for the lower-triangular L of cholesky_in_place (x: n values).
inline void forward_substitute(const Eigen::MatrixXd& L, double* x) {
  const Eigen::Index n = L.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* l_j = L.col(j).data();
    const double x_j = x[j] / l_j[j];
    x[j] = x_j;
    for (Eigen::Index i = j + 1; i < n; ++i) x[i] -= l_j[i] * x_j;
  }
}

/// x ← L⁻ᵀ x for the lower-triangular L of cholesky_in_place (x: n values).
inline void back_substitute(const Eigen::MatrixXd& L, double* x) {
  const Eigen::Index n = L.rows();
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    const double* l_j = L.col(j).data();
    double sum = x[j];
    for (Eigen::Index i = j + 1; i < n; ++i) sum -= l_j[i] * x[i];
    x[j] = sum / l_j[j];
  }
}

}  // namespace flexref::constraint
