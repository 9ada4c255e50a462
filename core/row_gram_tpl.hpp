#pragma once
/// \file row_gram_tpl.hpp
/// The Gram matrix G = J_r J_rᵀ of a set of constraint rows, sparse (the Schur complement's
/// pattern with M = I: core/schur_pattern_tpl.hpp) and factored by the sparse LDLᵀ
/// (core/sparse_ldl_tpl.hpp), in any scalar type S: the multipliers of other rows that give the
/// same reactions, and the test that all rows are clearly independent, which spares the dense
/// rank-revealing QR at setup where no row is redundant (docs/decisions.md, "Constrained systems
/// at scale"). Allocates: setup and rare paths.
#include <Eigen/Core>
#include <cmath>
#include <numeric>
#include <vector>

#include "core/constraint_jacobian_tpl.hpp"
#include "core/schur_pattern_tpl.hpp"
#include "core/sparse_ldl_tpl.hpp"

namespace flexref::core {

/// Smallest pivot of the LDLᵀ of the row-normalized Gram matrix (unit diagonal) at which all rows
/// count as independent without the rank-revealing QR: pivot k is the squared distance of row k's
/// direction from the span of the rows before it in the pivot order, so 1e-8 keeps every row
/// 1e-4 away from the others' span, six orders above the QR's rank threshold
/// kRedundantRowTolerance = 1e-10 (rows nearer go to the QR, which decides).
inline constexpr double kClearlyIndependentPivot = 1e-8;

/// G = J_r J_rᵀ over `rows` factored (false at a zero pivot); `pattern` and `ldl` receive it.
template <typename S>
bool factor_row_gram(const ConstraintJacobianTpl<S>& J, const std::vector<int>& rows,
                     SchurPattern& pattern, SparseLdlTpl<S>& ldl) {
  pattern.build(rows, J);
  ldl.analyze(static_cast<int>(rows.size()), pattern.column_start, pattern.row_index);
  Eigen::Matrix<S, Eigen::Dynamic, 1> G(pattern.nonzeros());
  for (int p = 0; p < pattern.nonzeros(); ++p) {
    G(p) = pattern.entry(p, J.all_values(), J.all_values(), false);
  }
  return ldl.factor_symmetric(G);
}

/// Whether every row of J is clearly independent of the others (kClearlyIndependentPivot, on
/// the rows scaled to unit length: the scale of the QR's rank decision). A zero row is not.
template <typename S>
bool rows_clearly_independent(const ConstraintJacobianTpl<S>& J) {
  using std::sqrt;
  ConstraintJacobianTpl<S> unit = J;
  for (int r = 0; r < J.rows(); ++r) {
    const S norm = sqrt(J.row_squared_norm(r));
    if (!(norm > S(0))) return false;
    for (int k = 0; k < 2; ++k) {
      if (unit.slot(r, k).body >= 0) unit.values(r, k) /= norm;
    }
  }
  std::vector<int> all(static_cast<std::size_t>(J.rows()));
  std::iota(all.begin(), all.end(), 0);
  SchurPattern pattern;
  SparseLdlTpl<S> ldl;
  if (!factor_row_gram(unit, all, pattern, ldl)) return false;
  return J.rows() == 0 || ldl.d().minCoeff() >= S(kClearlyIndependentPivot);
}

/// The multipliers on `rows` that give the generalized constraint force F = −Σ_r λ_r J_rᵀ: the
/// same reactions on another basis of the rows' span (any two independent row sets of the same
/// rank span it), from the normal equations (J_r J_rᵀ) λ = −J_r F.
template <typename S>
Eigen::Matrix<S, Eigen::Dynamic, 1> multipliers_on_rows(
    const ConstraintJacobianTpl<S>& J, const std::vector<int>& rows,
    const Eigen::Matrix<S, Eigen::Dynamic, 1>& force) {
  SchurPattern pattern;
  SparseLdlTpl<S> ldl;
  factor_row_gram(J, rows, pattern, ldl);
  const auto m = static_cast<Eigen::Index>(rows.size());
  Eigen::Matrix<S, Eigen::Dynamic, 1> x(m), lambda(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    x(k) = -J.row_dot(rows[static_cast<std::size_t>(pattern.order[static_cast<std::size_t>(k)])],
                      force);
  }
  ldl.solve_in_place(x);
  for (Eigen::Index k = 0; k < m; ++k) lambda(pattern.order[static_cast<std::size_t>(k)]) = x(k);
  return lambda;
}

}  // namespace flexref::core
