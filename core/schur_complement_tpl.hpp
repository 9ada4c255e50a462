#pragma once
/// \file schur_complement_tpl.hpp
/// The Schur complement of the ideal joints' index-1 system and its factorization, written once
/// for any scalar type S (docs/design/model.md, "Ideal joints"):
///
///   [M  Jᵀ] [v̇]   [Q]          A λ = J M⁻¹ Q − γ,   A = J M⁻¹ Jᵀ,
///   [J  0 ] [λ] = [γ],
///
/// over the rows an evaluation enforces (J_a: the independent rows its tracker holds, or rows
/// chosen again for it: core/row_selection_tpl.hpp), with M⁻¹ applied body by body by the model
/// (a rigid body's diag(m, I_Br) inverse, a flexible body's structured solve; the rows a body's
/// motion fixes stay zero). The scratch every constrained evaluation fills is here too.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/constraint_equations.hpp"

namespace flexref::core {

/// A configuration where the independent constraint rows became dependent (the Schur complement
/// J M⁻¹ Jᵀ lost rank): no multiplier is determined. Names the joint whose row fell out.
class SingularConfigurationError : public std::runtime_error {
 public:
  SingularConfigurationError(std::string joint, double time, const std::string& what)
      : std::runtime_error(what), joint_(std::move(joint)), time_(time) {}
  const std::string& joint() const { return joint_; }
  double time() const { return time_; }

 private:
  std::string joint_;
  double time_;
};

/// Smallest pivot of the Schur complement's LDLᵀ relative to its largest below which the
/// configuration counts as singular: ~1e4 ε above the round-off of a rank-deficient A (whose lost
/// pivot is ~ε times the largest), far below the pivot ratios of assembled mechanisms (the
/// Andrews squeezer's is ~1e-5 at worst, measured over its horizon).
inline constexpr double kSingularPivotRatio = 1e-12;

/// Scratch of one constrained evaluation, sized once (allocation-free evaluations). It holds
/// nothing an evaluation reads from an earlier one: `active` and `selection_ratio` start from
/// the caller's tracker at every evaluation (core/constraint_tracker.hpp) and end as the rows
/// this evaluation enforced and the multipliers' rows (core/joint_multipliers_tpl.hpp).
template <typename S>
struct ConstraintSolveTpl {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  ConstraintRowsTpl<S> rows;
  std::vector<int> active;  ///< the rows this evaluation enforces (indices into rows)
  /// Per active row, the bodies it acts on (−1: the ground), cached by factor_constraints: A and
  /// the crossing product are sparse — entry (i, j) is non-zero only where rows i and j share a
  /// body.
  std::vector<std::array<int, 2>> active_bodies;
  Matrix Y;  ///< N × m_a: M⁻¹ J_aᵀ
  Matrix A;  ///< m_a × m_a: J_a M⁻¹ J_aᵀ
  Eigen::LDLT<Matrix> ldlt;
  Vector rhs;            ///< m_a
  Vector lambda;         ///< m_a: the multipliers of the active rows
  Vector x;              ///< N: stacked accelerations (free in, constrained out)
  Vector force;          ///< N: the generalized constraint force −J_aᵀ λ
  Vector v;              ///< N: stacked velocities (stabilization)
  Vector rate;           ///< m: J v + Φ_t of all rows (stabilization, projection)
  Vector column;         ///< widest body block
  Vector out;            ///< widest body block
  S pivot_ratio = S(1);  ///< smallest/largest |pivot| of the last factorization
  /// Whether this solve chose its rows again (a rank-revealing QR at its state) instead of taking
  /// its tracker's as they were: its tracker's rows have become ill-conditioned there.
  bool rows_chosen = false;
  /// The pivot ratio the active rows were chosen at (the tracker's, or this evaluation's when it
  /// chose them again); 0: take the first factorization's.
  S selection_ratio = S(0);
  Matrix crossing;  ///< m_a × m_a: J_a,accepted M⁻¹ J_aᵀ (the orientation test)
  Eigen::PartialPivLU<Matrix> crossing_lu;

  /// Every Eigen decomposition here is computed once at construction (on an identity or an
  /// empty matrix): a decomposition never computed holds an uninitialized ComputationInfo, which
  /// moving the scratch would copy (UBSan: invalid enum load).
  ConstraintSolveTpl() { ldlt.compute(Matrix::Identity(0, 0)); }
  ConstraintSolveTpl(int rows_count, const VelocityLayout& layout, std::vector<int> active_rows) {
    rows.resize(rows_count, layout.size());
    active = std::move(active_rows);
    active_bodies.assign(active.size(), {-1, -1});
    const auto m = static_cast<Eigen::Index>(active.size());
    const Eigen::Index n = layout.size();
    Y = Matrix::Zero(n, m);
    A = Matrix::Zero(m, m);
    ldlt.compute(Matrix::Identity(m, m));
    rhs = Vector::Zero(m);
    lambda = Vector::Zero(m);
    x = Vector::Zero(n);
    force = Vector::Zero(n);
    v = Vector::Zero(n);
    rate = Vector::Zero(rows_count);
    int widest = 0;
    for (std::size_t b = 0; b + 1 < layout.offsets.size(); ++b) {
      widest = std::max(widest, layout.width(static_cast<int>(b)));
    }
    column = Vector::Zero(widest);
    out = Vector::Zero(widest);
    crossing = Matrix::Zero(m, m);
    crossing_lu = Eigen::PartialPivLU<Matrix>(m);
  }
};

/// True for the bodies[k] a row acts on that count once: not the ground (−1), not a repeat.
inline bool distinct_body(const std::array<int, 2>& bodies, std::size_t k) {
  return bodies[k] >= 0 && !(k == 1 && bodies[1] == bodies[0]);
}

/// Σ over the bodies b of active row i of J_row,b · Y_b,j: entry (i, j) of J_rows M⁻¹ J_aᵀ for
/// rows J_rows with the sparsity of the active rows (J_row is zero outside row i's bodies).
template <typename S>
S sparse_row_product(const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J, int row,
                     const std::array<int, 2>& bodies, const VelocityLayout& layout,
                     const ConstraintSolveTpl<S>& s, Eigen::Index j) {
  S sum = S(0);
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    if (!distinct_body(bodies, k)) continue;
    const int offset = layout.offset(bodies[k]);
    const int width = layout.width(bodies[k]);
    sum += J.row(row).segment(offset, width).dot(s.Y.col(j).segment(offset, width));
  }
  return sum;
}

/// True when active rows i and j act on a common body (else A_ij = 0).
inline bool share_body(const std::array<int, 2>& a, const std::array<int, 2>& b) {
  return (a[0] >= 0 && (a[0] == b[0] || a[0] == b[1])) ||
         (a[1] >= 0 && (a[1] == b[0] || a[1] == b[1]));
}

/// Y = M⁻¹ J_aᵀ, A = J_a Y and A's LDLᵀ for the active rows of s.rows.J. apply_inverse_mass(b,
/// rhs, out) writes M_b⁻¹ rhs into out (body b's block width; the rows the body's motion fixes
/// stay zero). Returns false (s.pivot_ratio set) when A is singular by kSingularPivotRatio.
template <typename S, typename ApplyInverseMass>
bool factor_constraints(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                        ApplyInverseMass&& apply_inverse_mass, ConstraintSolveTpl<S>& s) {
  using std::abs;
  const auto m = static_cast<Eigen::Index>(s.active.size());
  s.Y.setZero();
  for (Eigen::Index i = 0; i < m; ++i) {
    const int row = s.active[static_cast<std::size_t>(i)];
    auto& bodies = s.active_bodies[static_cast<std::size_t>(i)];
    bodies = equations.row_bodies(row);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      if (!distinct_body(bodies, k)) continue;
      const int b = bodies[k];
      const int offset = layout.offset(b);
      const int width = layout.width(b);
      s.column.head(width) = s.rows.J.row(row).segment(offset, width).transpose();
      apply_inverse_mass(b, s.column.head(width), s.out.head(width));
      s.Y.col(i).segment(offset, width) = s.out.head(width);
    }
  }
  // A_ij = Σ over the bodies row i acts on of J_i,b · Y_b,j: zero unless rows i and j share a
  // body (Y_b,j is zero outside row j's bodies).
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto& bodies_i = s.active_bodies[static_cast<std::size_t>(i)];
    for (Eigen::Index j = 0; j <= i; ++j) {
      const S sum = share_body(bodies_i, s.active_bodies[static_cast<std::size_t>(j)])
                        ? sparse_row_product(s.rows.J, s.active[static_cast<std::size_t>(i)],
                                             bodies_i, layout, s, j)
                        : S(0);
      s.A(i, j) = sum;
      s.A(j, i) = sum;
    }
  }
  if (m == 0) {
    s.pivot_ratio = S(1);
    return true;
  }
  s.ldlt.compute(s.A);
  const auto d = s.ldlt.vectorD();
  S smallest = abs(d(0));
  S largest = abs(d(0));
  for (Eigen::Index k = 1; k < m; ++k) {
    smallest = std::min<S>(smallest, abs(d(k)));
    largest = std::max<S>(largest, abs(d(k)));
  }
  s.pivot_ratio = largest > S(0) ? S(smallest / largest) : S(0);
  return s.ldlt.info() == Eigen::Success && s.pivot_ratio > S(kSingularPivotRatio);
}

}  // namespace flexref::core
