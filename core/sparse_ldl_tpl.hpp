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
/// symbolic phase finds the elimination tree, each column's count of L and the reach of each
/// column's entries in the tree — row k of L's pattern — (allocating, once per pattern); the
/// numeric phase computes row k of L by a sparse triangular solve over that stored reach. Davis
/// finds the reach again in every numeric factorization; stored, the numeric phase of the
/// Schur complement on Andrews' squeezer (41 rows) takes about half the time (docs/decisions.md).
/// The LU form is the same solve done twice: for a
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
  /// rows at row_index[column_start[k] .. column_start[k + 1]): the elimination tree, L's
  /// pattern, and each row's reach in the order the numeric phase visits it. Allocates.
  void analyze(int n, const std::vector<int>& column_start, const std::vector<int>& row_index) {
    n_ = n;
    Ap_ = Eigen::Map<const Ints>(column_start.data(), static_cast<Eigen::Index>(n) + 1);
    Ai_ = Eigen::Map<const Ints>(row_index.data(), Ap_(n));
    Ints parent = Ints::Constant(n, -1);
    Ints flag = Ints::Constant(n, -1);
    Ints count = Ints::Zero(n);
    for (int k = 0; k < n; ++k) {
      flag[k] = k;
      for (int p = Ap_[k]; p < Ap_[k + 1]; ++p) {
        for (int i = Ai_[p]; i < k && flag[i] != k; i = parent[i]) {
          if (parent[i] == -1) parent[i] = k;
          ++count[i];
          flag[i] = k;
        }
      }
    }
    Lp_.setZero(n + 1);
    for (int k = 0; k < n; ++k) Lp_[k + 1] = Lp_[k] + count[k];
    // Row k of L's pattern is the reach of A's column k in the elimination tree, visited in a
    // topological order (Davis's ldl_numeric). It depends on the pattern alone: found here once,
    // with the position in L of each entry (k, i), so that the numeric phase only computes.
    Li_.setZero(Lp_[n]);
    reach_start_.setZero(n + 1);
    reach_.setZero(Lp_[n]);
    reach_entry_.setZero(Lp_[n]);
    Ints stack = Ints::Zero(n);
    flag.setConstant(-1);
    count.setZero();
    int r = 0;
    for (int k = 0; k < n; ++k) {
      reach_start_[k] = r;
      int top = n;
      flag[k] = k;
      for (int p = Ap_[k]; p < Ap_[k + 1]; ++p) {
        int i = Ai_[p];
        int length = 0;
        for (; flag[i] != k; i = parent[i]) {
          stack[length++] = i;
          flag[i] = k;
        }
        while (length > 0) stack[--top] = stack[--length];
      }
      for (; top < n; ++top) {
        const int i = stack[top];
        const int entry = Lp_[i] + count[i]++;
        Li_[entry] = k;
        reach_[r] = i;
        reach_entry_[r] = entry;
        ++r;
      }
    }
    reach_start_[n] = r;
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
  bool factor_symmetric(const Vector& upper) { return factor<true>(upper, upper); }
  /// L D W̃ᵀ of the structurally symmetric C with C(i, k) = upper[p] and C(k, i) = lower[p] for
  /// pattern entry p at row i, column k (i ≤ k; the diagonal's in both).
  bool factor_unsymmetric(const Vector& upper, const Vector& lower) {
    return factor<false>(upper, lower);
  }
  /// D, in the pivot order.
  const Vector& d() const { return d_; }

  /// x ← A⁻¹ x after a factor_symmetric that succeeded (x in the pivot order).
  template <typename X>
  void solve_in_place(X& x) const {
    for (int j = 0; j < n_; ++j) {
      const S xj = x(j);
      for (int p = Lp_[j]; p < Lp_[j + 1]; ++p) x(Li_[p]) -= Lx_(p) * xj;
    }
    for (int j = 0; j < n_; ++j) x(j) /= d_(j);
    for (int j = n_ - 1; j >= 0; --j) {
      S xj = x(j);
      for (int p = Lp_[j]; p < Lp_[j + 1]; ++p) xj -= Lx_(p) * x(Li_[p]);
      x(j) = xj;
    }
  }

 private:
  /// Symmetric: LDLᵀ (lower unread, W̃ = L); else L D W̃ᵀ. A template argument so that the
  /// symmetric factorization's inner loop carries no second solve or test.
  template <bool symmetric>
  bool factor(const Vector& upper, const Vector& lower) {
    for (int k = 0; k < n_; ++k) {
      // y and z are zero outside the entries of the row being computed: each is cleared
      // where it is read.
      for (int p = Ap_[k]; p < Ap_[k + 1]; ++p) {
        const int i = Ai_[p];
        y_(i) += upper(p);
        if constexpr (!symmetric) {
          if (i < k) z_(i) += lower(p);
        }
      }
      S d = y_(k);
      y_(k) = S(0);
      for (int r = reach_start_[k]; r < reach_start_[k + 1]; ++r) {
        const int i = reach_[r];
        const S yi = y_(i);
        const S zi = symmetric ? yi : z_(i);
        y_(i) = S(0);
        if constexpr (!symmetric) z_(i) = S(0);
        // Column i's entries above row k (the rows of L before k), then L(k, i) itself.
        const int end = reach_entry_[r];
        for (int p = Lp_[i]; p < end; ++p) {
          y_(Li_[p]) -= Lx_(p) * yi;  // L u = C(0:k, k)
          if constexpr (!symmetric) {
            z_(Li_[p]) -= Wx_(p) * zi;  // W̃ z = C(k, 0:k)ᵀ, z = D L(k, :)ᵀ
          }
        }
        // L(k, i) = z_i / d_i; W̃(k, i) = U(i, k) / d_i = y_i / d_i (equal when symmetric).
        const S l = zi / d_(i);
        d -= l * yi;
        Lx_(end) = l;
        if constexpr (!symmetric) Wx_(end) = yi / d_(i);
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
  Ints Ap_, Ai_;  ///< the upper triangle's pattern
  Ints Lp_, Li_;  ///< L's (and W̃'s) pattern by columns
  /// Row k of L: columns reach_[reach_start_[k] .. reach_start_[k + 1]) in the order they are
  /// eliminated, each entry at reach_entry_ in Li_, Lx_ and Wx_.
  Ints reach_start_, reach_, reach_entry_;
  Vector Lx_, Wx_, d_, y_, z_;
};

}  // namespace flexref::core
