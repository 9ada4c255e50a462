#pragma once
/// \file row_selection_tpl.hpp
/// Which constraint rows a solve enforces (docs/joints.md, "Redundant constraints"): the
/// independent rows, chosen at the initial configuration by a rank-revealing QR of Jᵀ (redundant
/// rows of an over-constrained mechanism — a planar loop of revolute joints in 3D, the Bricard
/// linkage — carry no multiplier of their own), and chosen again in motion where the rows in force
/// became ill-conditioned while all rows kept their rank. A rank drop of all rows is a singular
/// configuration (a four-bar's dead point): SingularConfigurationError names the joint.
#include <Eigen/QR>
#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "core/row_gram_tpl.hpp"
#include "core/schur_complement_tpl.hpp"

namespace flexref::core {

/// Relative threshold of the rank-revealing QR that picks the independent rows at the initial
/// configuration: redundancy is structural, its pivots are ~ε relative; 1e-10 keeps rows whose
/// independence is merely weak (they become a singular configuration if they lose it later).
inline constexpr double kRedundantRowTolerance = 1e-10;
/// Pivot ratio below which the independent rows are chosen again at the current configuration:
/// rows independent at the initial configuration can become dependent among themselves later
/// while the whole set keeps its rank (a planar loop in 3D: which out-of-plane rows are
/// independent depends on the pose), and an ill-conditioned A loses ~log10(1/ratio) digits of λ.
inline constexpr double kReselectPivotRatio = 1e-8;
/// Fall of the pivot ratio since the rows were chosen beyond which they are chosen again: the
/// rows set aside follow the enforced ones through the dependency, their drift the enforced rows'
/// amplified by ~1/√(fall) (the pivots are squares of J_a's singular values), and a fall of 10
/// keeps that at ~3; a looser fall let a Bricard linkage's set-aside row drift beyond the output
/// check's bound (docs/joints.md, "Redundant constraints", has the measurement). Where the rows
/// chosen anew are the same, the reference is the current ratio, so a mechanism whose
/// conditioning merely varies pays one rank-revealing QR per tenfold fall.
inline constexpr double kReselectPivotFall = 1e-1;

/// Jᵀ with each row of J scaled to unit length (a zero row stays zero): rank decisions on it are
/// relative to each row's own scale, not to the largest row's — a joint whose arm is 1e3 times
/// another's does not make the other's rows look dependent, and a row is dependent when its
/// direction is, whatever its size. Allocates.
template <typename S>
Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> row_normalized_transpose(
    const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) {
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> Jt = J.transpose();
  for (Eigen::Index r = 0; r < Jt.cols(); ++r) {
    const S norm = Jt.col(r).norm();
    if (norm > S(0)) Jt.col(r) /= norm;
  }
  return Jt;
}

/// The independent rows of J (ascending). The rank r is a column-pivoted Householder QR's of Jᵀ
/// with each row scaled to unit length first (row_normalized_transpose), decided with
/// kRedundantRowTolerance relative to the largest pivot (~1 for unit columns). Which m − r rows
/// are set aside is not left to the pivoting order (in exact arithmetic every row of a dependency
/// is equally dependent, so round-off would choose): the dependencies C (m × k, k = m − r, the
/// null space of the scaled Jᵀ from the QR, orthonormalized) are kept by the rows that set aside
/// leave the best-conditioned rest — the k rows where C's k × k block is best conditioned, a
/// column-pivoted QR of Cᵀ's first k pivots (the rows left are independent exactly when that
/// block is invertible, and as far from dependent as it is from singular). A Bricard linkage's
/// single dependency thus sets aside the row with the largest share in it, not one whose share
/// passes through zero later in the motion. Allocates.
template <typename S>
std::vector<int> independent_rows(const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  std::vector<int> rows;
  if (J.rows() == 0) return rows;
  Eigen::ColPivHouseholderQR<Matrix> qr(row_normalized_transpose<S>(J));
  qr.setThreshold(S(kRedundantRowTolerance));
  const Eigen::Index m = J.rows();
  const Eigen::Index rank = qr.rank();
  if (rank == m) {
    for (Eigen::Index k = 0; k < m; ++k) rows.push_back(static_cast<int>(k));
    return rows;
  }
  // Jᵀ P = Q [R11 R12; 0 0]: the null space is P [−R11⁻¹ R12; I].
  const Eigen::Index k = m - rank;
  const Matrix R = qr.matrixR().topRows(rank);
  Matrix Y(m, k);
  Y.topRows(rank) = -R.leftCols(rank).template triangularView<Eigen::Upper>().solve(R.rightCols(k));
  Y.bottomRows(k).setIdentity();
  const Matrix C = qr.colsPermutation() * Y;
  const Matrix C_orthonormal =
      Eigen::HouseholderQR<Matrix>(C).householderQ() * Matrix::Identity(m, k);
  const Eigen::ColPivHouseholderQR<Matrix> pick(C_orthonormal.transpose());
  std::vector<bool> set_aside(static_cast<std::size_t>(m), false);
  for (Eigen::Index i = 0; i < k; ++i) {
    set_aside[static_cast<std::size_t>(pick.colsPermutation().indices()(i))] = true;
  }
  for (Eigen::Index i = 0; i < m; ++i) {
    if (!set_aside[static_cast<std::size_t>(i)]) rows.push_back(static_cast<int>(i));
  }
  return rows;
}

/// The independent rows of J given by its blocks: all rows where they are clearly independent
/// (rows_clearly_independent: a sparse LDLᵀ of their Gram matrix, near-linear in the rows), else
/// the dense rank-revealing choice above on J made dense (over-constrained mechanisms and rows
/// near dependence: small mechanisms, or a rare path). Allocates.
template <typename S>
std::vector<int> independent_rows(const ConstraintJacobianTpl<S>& J) {
  if (rows_clearly_independent(J)) {
    std::vector<int> rows(static_cast<std::size_t>(J.rows()));
    std::iota(rows.begin(), rows.end(), 0);
    return rows;
  }
  return independent_rows<S>(J.dense());
}

/// The joint whose row falls out of the independent set at the current rows (for the message of
/// a singular configuration): the first active row a rank-revealing QR of J_aᵀ leaves out.
/// Allocates (the failure path only).
template <typename S>
int singular_joint(const ConstraintEquationsTpl<S>& equations, const ConstraintSolveTpl<S>& s) {
  const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> J = s.rows.jacobian.dense();
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> J_a(static_cast<Eigen::Index>(s.active.size()),
                                                       J.cols());
  for (std::size_t i = 0; i < s.active.size(); ++i) {
    J_a.row(static_cast<Eigen::Index>(i)) = J.row(s.active[i]);
  }
  const std::vector<int> kept = independent_rows<S>(J_a);
  for (std::size_t i = 0; i < s.active.size(); ++i) {
    if (std::find(kept.begin(), kept.end(), static_cast<int>(i)) == kept.end()) {
      return equations.joint_of_row(s.active[i]);
    }
  }
  return equations.joint_of_row(s.active.back());
}

/// Throws SingularConfigurationError for the factorization that failed at time t.
template <typename S>
[[noreturn]] void throw_singular(const ConstraintEquationsTpl<S>& equations,
                                 const ConstraintSolveTpl<S>& s, double t) {
  const int joint = singular_joint(equations, s);
  const std::string& name = equations.joint_name(joint);
  throw SingularConfigurationError(
      name, t,
      "singular configuration at t = " + std::to_string(t) + ": the constraints of joint '" + name +
          "' became dependent on the others (smallest/largest pivot of J M^-1 J^T " +
          std::to_string(static_cast<double>(s.pivot_ratio)) +
          "); the mechanism is at a dead point or a bifurcation, where its multipliers and "
          "motion are not determined");
}

/// factor_constraints on s.active, and when A is singular or ill-conditioned
/// (kReselectPivotRatio), or its pivot ratio fell by kReselectPivotFall since the rows were
/// chosen (s.selection_ratio; 0: this factorization's), the independent rows chosen again at the
/// current configuration (a column-pivoted QR of all rows, allocating: the rare path) into
/// s.active and A factored anew (s.rows_chosen set); s.selection_ratio then is the ratio they
/// were chosen at.
/// Returns false when the rows have lost rank (fewer independent rows than before: a singular
/// configuration) or A is still singular.
template <typename S, typename ApplyInverseMass>
bool choose_rows(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                 ApplyInverseMass&& apply_inverse_mass, ConstraintSolveTpl<S>& s) {
  const bool ok = factor_constraints(equations, layout, apply_inverse_mass, s);
  if (!(s.selection_ratio > S(0))) s.selection_ratio = s.pivot_ratio;
  if (ok && s.pivot_ratio >= S(kReselectPivotRatio) &&
      s.pivot_ratio >= S(kReselectPivotFall) * s.selection_ratio) {
    return true;
  }
  s.rows_chosen = true;
  std::vector<int> rows = independent_rows<S>(s.rows.jacobian);
  if (rows.size() < s.active.size()) return false;
  rows.resize(s.active.size());  // the rank cannot grow for a mechanism that moves continuously
  if (rows == s.active) {
    s.selection_ratio = s.pivot_ratio;
    return ok;
  }
  s.active = std::move(rows);
  const bool factored = factor_constraints(equations, layout, apply_inverse_mass, s);
  s.selection_ratio = s.pivot_ratio;
  return factored;
}

}  // namespace flexref::core
