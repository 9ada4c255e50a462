#pragma once
/// \file sparse_ldl_tpl.hpp
/// Sparse LDLᵀ and LU factorizations of a structurally symmetric matrix, in any scalar type S,
/// without pivoting and without allocation in the numeric phase (docs/decisions.md,
/// "Constrained systems at scale"). The matrix comes in its pivot order (a fill-reducing order
/// the caller chose: core/schur_pattern_tpl.hpp) as the upper triangle of a compressed-column
/// pattern: column k holds rows i ≤ k, the diagonal included.
///
/// The algorithm is T. A. Davis's up-looking LDL (Algorithm 849: A concise sparse Cholesky
/// factorization package, ACM TOMS 31(4), 2005 — the one behind Eigen's SimplicialLDLT): the
/// symbolic phase finds the elimination tree and each column's count of L (allocating, once per
/// pattern); the numeric phase computes row k of L by a sparse triangular solve whose pattern is
/// the reach of column k's entries in the tree. The LU form is the same solve done twice: for a
/// structurally symmetric C = L D W̃ᵀ (L, W̃ unit lower of one pattern: U = D W̃ᵀ), column k of U
/// solves L u = C(0:k, k) and row k of L solves (D W̃ᵀ)ᵀ l = C(k, 0:k), both over the same reach.
/// The sign of det C is the product of D's signs (a symmetric permutation leaves it unchanged).
#include <Eigen/Core>
#include <vector>

namespace flexref::core {

template <typename S>
class SparseLdlTpl {
 public:
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  /// Integer arrays indexed by int without sign conversions.
  using Ints = Eigen::VectorXi;

  /// The symbolic phase for an n × n matrix whose upper triangle (pivot order) has column k's
  /// rows at row_index[column_start[k] .. column_start[k + 1]). Allocates.
  void analyze(int n, const std::vector<int>& column_start, const std::vector<int>& row_index) {
    n_ = n;
    Ap_ = Eigen::Map<const Ints>(column_start.data(), static_cast<Eigen::Index>(n) + 1);
    Ai_ = Eigen::Map<const Ints>(row_index.data(), Ap_(n));
    parent_.setConstant(n, -1);
    flag_.setConstant(n, -1);
    count_.setZero(n);
    pattern_.setZero(n);
    for (int k = 0; k < n; ++k) {
      flag_[k] = k;
      for (int p = Ap_[k]; p < Ap_[k + 1]; ++p) {
        for (int i = Ai_[p]; i < k && flag_[i] != k; i = parent_[i]) {
          if (parent_[i] == -1) parent_[i] = k;
          ++count_[i];
          flag_[i] = k;
        }
      }
    }
    Lp_.setZero(n + 1);
    for (int k = 0; k < n; ++k) Lp_[k + 1] = Lp_[k] + count_[k];
    Li_.setZero(Lp_[n]);
    Lx_ = Vector::Zero(Lp_[n]);
    Wx_ = Vector::Zero(Lp_[n]);
    d_ = Vector::Zero(n);
    y_ = Vector::Zero(n);
    z_ = Vector::Zero(n);
  }

  int size() const { return n_; }
  /// Non-zeros of L (below the diagonal).
  int factor_nonzeros() const { return n_ > 0 ? Lp_[n_] : 0; }

  /// LDLᵀ of the symmetric matrix with upper-triangle values `upper` (one per pattern entry).
  /// False at a zero pivot (D then holds the pivots up to it, the rest zero).
  bool factor_symmetric(const Vector& upper) { return factor(upper, upper, true); }
  /// L D W̃ᵀ of the structurally symmetric C with C(i, k) = upper[p] and C(k, i) = lower[p] for
  /// pattern entry p at row i, column k (i ≤ k; the diagonal's in both).
  bool factor_unsymmetric(const Vector& upper, const Vector& lower) {
    return factor(upper, lower, false);
  }
  /// D, in the pivot order.
  const Vector& d() const { return d_; }

  /// x ← A⁻¹ x after factor_symmetric (x in the pivot order).
  template <typename X>
  void solve_in_place(X& x) const {
    for (int j = 0; j < n_; ++j) {
      const S xj = x(j);
      for (int p = Lp_[j]; p < Lp_[j] + count_[j]; ++p) x(Li_[p]) -= Lx_(p) * xj;
    }
    for (int j = 0; j < n_; ++j) x(j) /= d_(j);
    for (int j = n_ - 1; j >= 0; --j) {
      S xj = x(j);
      for (int p = Lp_[j]; p < Lp_[j] + count_[j]; ++p) xj -= Lx_(p) * x(Li_[p]);
      x(j) = xj;
    }
  }

 private:
  bool factor(const Vector& upper, const Vector& lower, bool symmetric) {
    for (int k = 0; k < n_; ++k) {
      y_(k) = S(0);
      z_(k) = S(0);
      int top = n_;
      flag_[k] = k;
      count_[k] = 0;
      for (int p = Ap_[k]; p < Ap_[k + 1]; ++p) {
        int i = Ai_[p];
        y_(i) += upper(p);
        if (!symmetric && i < k) z_(i) += lower(p);
        int length = 0;
        for (; flag_[i] != k; i = parent_[i]) {
          pattern_[length++] = i;
          flag_[i] = k;
        }
        while (length > 0) pattern_[--top] = pattern_[--length];
      }
      S d = y_(k);
      y_(k) = S(0);
      for (; top < n_; ++top) {
        const int i = pattern_[top];
        const S yi = y_(i);
        const S zi = symmetric ? yi : z_(i);
        y_(i) = S(0);
        z_(i) = S(0);
        const int end = Lp_[i] + count_[i];
        for (int p = Lp_[i]; p < end; ++p) {
          y_(Li_[p]) -= Lx_(p) * yi;                  // L u = C(0:k, k)
          if (!symmetric) z_(Li_[p]) -= Wx_(p) * zi;  // W̃ z = C(k, 0:k)ᵀ, z = D L(k, :)ᵀ
        }
        // L(k, i) = z_i / d_i; W̃(k, i) = U(i, k) / d_i = y_i / d_i (equal when symmetric).
        const S l = zi / d_(i);
        const S w = yi / d_(i);
        d -= l * yi;
        Li_[end] = k;
        Lx_(end) = l;
        Wx_(end) = w;
        ++count_[i];
      }
      if (!(d != S(0))) {
        for (int j = k; j < n_; ++j) d_(j) = S(0);
        return false;
      }
      d_(k) = d;
    }
    return true;
  }

  int n_ = 0;
  Ints Ap_, Ai_;       ///< the upper triangle's pattern
  Ints parent_;        ///< the elimination tree
  Ints flag_, count_;  ///< per column: visited mark, entries of L so far
  Ints pattern_;       ///< the reach of a column (a stack)
  Ints Lp_, Li_;       ///< L's (and W̃'s) pattern by columns
  Vector Lx_, Wx_, d_, y_, z_;
};

}  // namespace flexref::core
