#pragma once
/// \file small_cholesky.hpp
/// Cholesky factorization A = L Lᵀ and its triangular solves for the small dense symmetric
/// positive definite matrices of the reduced form (constraint/reduced_model.hpp: M_r, n_u × n_u,
/// and the closures' Schur complement, r × r), in plain loops over a column-major
/// Eigen::MatrixXd. At these sizes (a handful to a few tens) Eigen's dynamic-size LLT,
/// triangular solves and products spend more in their blocking and dispatch than in the
/// arithmetic (docs/reduced_coordinates.md, "Cost"). The factorization is the left-looking
/// (column by column) one, O(n³/6); the substitutions O(n²). Nothing allocates.
#include <Eigen/Core>
#include <cmath>

namespace flexref::constraint {

/// A = L Lᵀ in place, stored as N = L − diag(L) (A becomes N: zeros on and above the diagonal)
/// with 1/L(j,j) in `inverse_diagonal` and, if not null, L(j,j) in `diagonal` (n values each).
/// Reads A's lower triangle only. The zeros let the inner loop run over all n rows, a trip count
/// that does not change from column to column; the substitutions multiply by 1/L(j,j) (a
/// division on each step of their dependency chain costs several multiplications). Returns −1,
/// or the first column j whose pivot A(j,j) − Σ L(j,k)² is not positive (or NaN): A is not
/// positive definite and the factor is complete only left of j.
inline Eigen::Index cholesky_in_place(Eigen::MatrixXd& A, double* inverse_diagonal,
                                      double* diagonal = nullptr) {
  const Eigen::Index n = A.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    double* a_j = A.col(j).data();
    for (Eigen::Index k = 0; k < j; ++k) {
      const double l_jk = A(j, k);
      if (l_jk == 0.0) continue;  // a tree's M_r: bodies on different branches do not couple
      const double* n_k = A.col(k).data();
      for (Eigen::Index i = 0; i < n; ++i) a_j[i] -= l_jk * n_k[i];  // rows ≤ j: discarded
    }
    if (!(a_j[j] > 0.0)) return j;
    const double l_jj = std::sqrt(a_j[j]);
    const double inverse = 1.0 / l_jj;
    inverse_diagonal[j] = inverse;
    if (diagonal != nullptr) diagonal[j] = l_jj;
    for (Eigen::Index i = 0; i < n; ++i) a_j[i] = i > j ? a_j[i] * inverse : 0.0;
  }
  return -1;
}

/// x ← L⁻¹ x for the N and 1/diag(L) of cholesky_in_place (x: n values). Each x_j is a scalar
/// sum over the x_k already found: a column-oriented update of x, vectorized, would store x in
/// pairs and read x_j back alone, which store-to-load forwarding does not serve.
inline void forward_substitute(const Eigen::MatrixXd& N, const double* inverse_diagonal,
                               double* x) {
  const Eigen::Index n = N.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    double sum = x[j];
    for (Eigen::Index k = 0; k < j; ++k) {
      if (N(j, k) != 0.0) sum -= N(j, k) * x[k];
    }
    x[j] = sum * inverse_diagonal[j];
  }
}

/// x ← L⁻ᵀ x for the N and 1/diag(L) of cholesky_in_place (x: n values), as scalar sums.
inline void back_substitute(const Eigen::MatrixXd& N, const double* inverse_diagonal, double* x) {
  const Eigen::Index n = N.rows();
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    const double* n_j = N.col(j).data();
    double sum = x[j];
    for (Eigen::Index i = j + 1; i < n; ++i) {
      if (n_j[i] != 0.0) sum -= n_j[i] * x[i];  // zeros kept off the chain of subtractions
    }
    x[j] = sum * inverse_diagonal[j];
  }
}

/// X ← X L⁻ᵀ (each row x of X becomes L⁻¹ x) for the N and 1/diag(L) of cholesky_in_place: X's
/// columns (all its right-hand sides at once, contiguous) are scaled and subtracted whole.
inline void forward_substitute_rows(const Eigen::MatrixXd& N, const double* inverse_diagonal,
                                    Eigen::MatrixXd& X) {
  const Eigen::Index n = N.rows(), m = X.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    double* x_j = X.col(j).data();
    for (Eigen::Index c = 0; c < m; ++c) x_j[c] *= inverse_diagonal[j];
    for (Eigen::Index i = j + 1; i < n; ++i) {
      const double l_ij = N(i, j);
      if (l_ij == 0.0) continue;
      double* x_i = X.col(i).data();
      for (Eigen::Index c = 0; c < m; ++c) x_i[c] -= l_ij * x_j[c];
    }
  }
}

}  // namespace flexref::constraint
