#pragma once
/// \file constrained_solve_tpl.hpp
/// The multipliers of holonomic constraints and the constrained accelerations, written once for
/// any scalar type S (core::Model in double, the extended and quad references in S), and the
/// projections onto the constraint manifold. docs/design/model.md, "Ideal joints", index-1 form:
///
///   [M  Jᵀ] [v̇]   [Q]          A λ = J M⁻¹ Q − γ,   A = J M⁻¹ Jᵀ   (Schur complement)
///   [J  0 ] [λ] = [γ],         v̇ = M⁻¹ Q − M⁻¹ Jᵀ λ,
///
/// with M⁻¹ applied body by body by the model (a rigid body's diag(m, I_Br) inverse, a flexible
/// body's structured solve; the rows a body's motion fixes stay zero). Only the independent rows
/// enter (chosen once, at the initial configuration, by a rank-revealing QR of Jᵀ: redundant
/// rows of an over-constrained mechanism — a planar loop of revolute joints in 3D, the Bricard
/// linkage — carry no multiplier of their own, and the reactions are the minimum-norm
/// multipliers of all rows that give the same generalized force). A rank drop of A in motion is
/// a singular configuration (a four-bar's dead point): the solve throws
/// SingularConfigurationError naming the joint.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
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
/// keeps that at ~3. A Bricard linkage's set-aside row loses its share in the dependency in the
/// motion (t ≈ 1.2 s): the enforced rows' ratio falls from 6e-4 to 1e-5 there. With a fall of
/// 1e2 allowed, the set-aside row's drift reached 11 times the enforced rows' (5e-9 m at rtol
/// 1e-11) before the rows were chosen again, and its velocity drift, integrated afterwards,
/// carried the position drift to 2.9e-8 m, beyond the output check's bound (1e3 rtol relative,
/// core/joint_check.hpp). Where the rows chosen anew are the same, the reference is the current
/// ratio, so a mechanism whose conditioning merely varies pays one rank-revealing QR per tenfold
/// fall.
inline constexpr double kReselectPivotFall = 1e-1;
/// Cosine of the largest angle the active rows may turn through between two solves for the
/// orientation test to apply (rows_turned_little): 0.5 rad. The test reads the sign of
/// det(J_a,prev M⁻¹ J_aᵀ), which a dead point crossed flips; rows that turned by more can flip it
/// without one (Odeint's 0.4 s steps on a driven hinge were read as "passed between t = 0.2 and
/// t = 0.6"). The crossings the test exists for are stepped over by a few hundredths of a
/// radian (CVODE's step across the driven parallelogram's change point: 0.08 rad).
inline constexpr double kOrientationTestCosine = 0.87758256189037276;  // cos 0.5

/// Scratch of the constrained solve, sized once (allocation-free evaluations).
template <typename S>
struct ConstraintSolveTpl {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  ConstraintRowsTpl<S> rows;
  std::vector<int> active;  ///< the independent rows (indices into rows)
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
  /// The pivot ratio when the rows were last chosen (kReselectPivotFall); 0: not yet factored.
  S selection_ratio = S(0);
  /// The rows at the last constrained solve (all rows, m × N), its time, and whether there was
  /// one: a singular configuration passed between two solves turns the orientation of the rows
  /// (crossed_singularity).
  Matrix J_previous;
  double previous_time = 0.0;
  bool has_previous = false;
  Matrix crossing;  ///< m_a × m_a: J_a,previous M⁻¹ J_aᵀ
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
    J_previous = Matrix::Zero(rows_count, n);
    crossing = Matrix::Zero(m, m);
    crossing_lu = Eigen::PartialPivLU<Matrix>(m);
  }
};

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

/// The joint whose row falls out of the independent set at the current rows (for the message of
/// a singular configuration): the first active row a rank-revealing QR of J_aᵀ leaves out.
/// Allocates (the failure path only).
template <typename S>
int singular_joint(const ConstraintEquationsTpl<S>& equations, const ConstraintSolveTpl<S>& s) {
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> J_a(static_cast<Eigen::Index>(s.active.size()),
                                                       s.rows.J.cols());
  for (std::size_t i = 0; i < s.active.size(); ++i) {
    J_a.row(static_cast<Eigen::Index>(i)) = s.rows.J.row(s.active[i]);
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

/// factor_constraints, and when A is singular or ill-conditioned (kReselectPivotRatio), or its
/// pivot ratio fell by kReselectPivotFall since the rows were chosen, the
/// independent rows chosen again at the current configuration (a column-pivoted QR of all rows,
/// allocating: the rare path) and A factored anew. Returns false when the rows have lost rank
/// (fewer independent rows than before: a singular configuration) or A is still singular.
template <typename S, typename ApplyInverseMass>
bool factor_or_reselect(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                        ApplyInverseMass&& apply_inverse_mass, ConstraintSolveTpl<S>& s) {
  const bool ok = factor_constraints(equations, layout, apply_inverse_mass, s);
  if (!(s.selection_ratio > S(0))) s.selection_ratio = s.pivot_ratio;
  if (ok && s.pivot_ratio >= S(kReselectPivotRatio) &&
      s.pivot_ratio >= S(kReselectPivotFall) * s.selection_ratio) {
    return true;
  }
  std::vector<int> rows = independent_rows<S>(s.rows.J);
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

/// True when the active rows kept their orientation since the last solve: det(J_a,prev M⁻¹ J_aᵀ)
/// > 0. Both are bases of the rows' span; away from singular configurations and for the small
/// state changes between a solver's evaluations the product is close to A, symmetric positive
/// definite. When a configuration where the rows lose rank lies between the two (a four-bar's
/// change point, stepped over: A's pivot ratio falls as the square of the distance to it and
/// would flag it only within ~1e-6 of it), a singular value of J changes sign and the
/// determinant with it. s factored at the current rows (s.Y = M⁻¹ J_aᵀ).
template <typename S>
bool kept_orientation(const VelocityLayout& layout, ConstraintSolveTpl<S>& s) {
  const auto m = static_cast<Eigen::Index>(s.active.size());
  if (m == 0) return true;
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto& bodies_i = s.active_bodies[static_cast<std::size_t>(i)];
    for (Eigen::Index j = 0; j < m; ++j) {
      s.crossing(i, j) =
          share_body(bodies_i, s.active_bodies[static_cast<std::size_t>(j)])
              ? sparse_row_product(s.J_previous, s.active[static_cast<std::size_t>(i)], bodies_i,
                                   layout, s, j)
              : S(0);
    }
  }
  s.crossing_lu.compute(s.crossing);
  // The determinant's sign: the permutation's and the signs of U's diagonal (no product, which
  // could underflow).
  // The permutation's sign is the parity of its inversions (O(m²) comparisons, no scratch:
  // Eigen's PermutationMatrix::determinant allocates a mask).
  const auto& indices = s.crossing_lu.permutationP().indices();
  int sign = 1;
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = i + 1; j < m; ++j) {
      if (indices(i) > indices(j)) sign = -sign;
    }
  }
  const auto& lu = s.crossing_lu.matrixLU();
  for (Eigen::Index k = 0; k < m; ++k) {
    if (!(lu(k, k) != S(0))) return false;
    if (lu(k, k) < S(0)) sign = -sign;
  }
  return sign > 0;
}

/// Throws SingularConfigurationError for a singular configuration passed between two solves, at
/// t0 and t1 (kept_orientation): the joint of the active row with the smallest pivot of A's
/// pivoted LDLᵀ at t1, the row nearest to dependence on the others.
template <typename S>
[[noreturn]] void throw_singular_between(const ConstraintEquationsTpl<S>& equations,
                                         const ConstraintSolveTpl<S>& s, double t0, double t1) {
  using std::abs;
  const auto d = s.ldlt.vectorD();
  Eigen::Index smallest = 0;
  for (Eigen::Index k = 1; k < d.size(); ++k) {
    if (abs(d(k)) < abs(d(smallest))) smallest = k;
  }
  // vectorD is in the pivoted order: P A Pᵀ = L D Lᵀ, so pivot k is row transpositions⁻¹(k).
  Eigen::Matrix<S, Eigen::Dynamic, 1> unit = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(d.size());
  unit(smallest) = S(1);
  const Eigen::Matrix<S, Eigen::Dynamic, 1> original = s.ldlt.transpositionsP().transpose() * unit;
  Eigen::Index row = 0;
  for (Eigen::Index k = 0; k < original.size(); ++k) {
    if (original(k) != S(0)) row = k;
  }
  const std::string& name =
      equations.joint_name(equations.joint_of_row(s.active[static_cast<std::size_t>(row)]));
  throw SingularConfigurationError(
      name, t1,
      "singular configuration passed between t = " + std::to_string(t0) +
          " and t = " + std::to_string(t1) + ": the constraints of joint '" + name +
          "' became dependent on the others there (the rows' orientation turned; smallest/largest "
          "pivot of J M^-1 J^T now " +
          std::to_string(static_cast<double>(s.pivot_ratio)) +
          "); the mechanism passed a dead point or a bifurcation, where its multipliers and "
          "motion are not determined");
}

/// The largest angle the active rows turned through between the last solve and this one (each
/// row's direction on the bodies it acts on, previous against current): where it exceeds
/// kOrientationTestAngle the orientation test is not conclusive.
template <typename S>
bool rows_turned_little(const VelocityLayout& layout, const ConstraintSolveTpl<S>& s) {
  for (std::size_t i = 0; i < s.active.size(); ++i) {
    const int row = s.active[i];
    const std::array<int, 2>& bodies = s.active_bodies[i];
    S dot = S(0), previous = S(0), current = S(0);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      if (!distinct_body(bodies, k)) continue;
      const int offset = layout.offset(bodies[k]);
      const int width = layout.width(bodies[k]);
      const auto a = s.J_previous.row(row).segment(offset, width);
      const auto b = s.rows.J.row(row).segment(offset, width);
      dot += a.dot(b);
      previous += a.squaredNorm();
      current += b.squaredNorm();
    }
    using std::sqrt;
    if (dot < S(kOrientationTestCosine) * sqrt(previous * current)) return false;
  }
  return true;
}

/// The singular-configuration test between two solves (kept_orientation) for s factored at t,
/// then t's rows kept as the next solve's previous ones. Where the active rows alone turned —
/// they passed a configuration where they are dependent while all rows kept their rank — rows
/// chosen at the current configuration keep the orientation; otherwise the mechanism passed a
/// singular configuration between the two solves: throws SingularConfigurationError.
template <typename S, typename ApplyInverseMass>
void check_orientation(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                       ApplyInverseMass&& apply_inverse_mass, double t, ConstraintSolveTpl<S>& s) {
  // The test assumes the small changes between a solver's evaluations; where the rows turned
  // through more (an explicit solver's long steps on a smooth driven motion), it would read the
  // turn for a crossing: it is skipped, and the rows are the next solve's previous ones.
  if (s.has_previous && rows_turned_little(layout, s) && !kept_orientation(layout, s)) {
    std::vector<int> rows = independent_rows<S>(s.rows.J);
    rows.resize(std::min(rows.size(), s.active.size()));
    if (rows.size() == s.active.size() && rows != s.active) {
      s.active = std::move(rows);
      if (!factor_constraints(equations, layout, apply_inverse_mass, s)) {
        throw_singular(equations, s, t);
      }
    }
    if (!kept_orientation(layout, s)) throw_singular_between(equations, s, s.previous_time, t);
  }
  s.J_previous = s.rows.J;
  s.previous_time = t;
  s.has_previous = true;
}

/// Constrained accelerations: s.x holds the free accelerations M⁻¹ Q on entry (stacked, body
/// blocks as in layout) and the constrained ones on exit; s.rows evaluated at the state; λ of
/// the active rows in s.lambda and the generalized constraint force −J_aᵀ λ in s.force. Throws
/// SingularConfigurationError at a singular configuration (t names the time).
template <typename S, typename ApplyInverseMass>
void solve_constrained_accelerations(const ConstraintEquationsTpl<S>& equations,
                                     const VelocityLayout& layout,
                                     ApplyInverseMass&& apply_inverse_mass, double t,
                                     ConstraintSolveTpl<S>& s) {
  if (!factor_or_reselect(equations, layout, apply_inverse_mass, s)) {
    throw_singular(equations, s, t);
  }
  check_orientation(equations, layout, apply_inverse_mass, t, s);
  const auto m = static_cast<Eigen::Index>(s.active.size());
  // A λ = J_a x_free − γ_a
  for (Eigen::Index i = 0; i < m; ++i) {
    const int row = s.active[static_cast<std::size_t>(i)];
    s.rhs(i) = s.rows.J.row(row).dot(s.x) - s.rows.gamma(row);
  }
  s.lambda = s.ldlt.solve(s.rhs);
  // v̇ = x_free − Y λ;  F = −J_aᵀ λ
  s.x.noalias() -= s.Y * s.lambda;
  s.force.setZero();
  for (Eigen::Index i = 0; i < m; ++i) {
    const int row = s.active[static_cast<std::size_t>(i)];
    s.force.noalias() -= s.lambda(i) * s.rows.J.row(row).transpose();
  }
}

/// The correction δ = −M⁻¹ J_aᵀ A⁻¹ r of the stacked generalized coordinates (velocities, or
/// position increments (δp_Br, δφ_B, δq_f)) that removes the residual r of the active rows to
/// first order in the mass metric — the projection onto the constraint manifold of Hairer,
/// Lubich & Wanner (Geometric Numerical Integration, IV.4) with M as the metric. s must be
/// factored (factor_constraints) at the configuration. Writes δ into s.x.
template <typename S>
void constraint_correction(const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& residual,
                           ConstraintSolveTpl<S>& s) {
  const auto m = static_cast<Eigen::Index>(s.active.size());
  for (Eigen::Index i = 0; i < m; ++i) s.rhs(i) = residual(s.active[static_cast<std::size_t>(i)]);
  s.lambda = s.ldlt.solve(s.rhs);
  s.x.noalias() = -(s.Y * s.lambda);
}

/// Baumgarte stabilization of the accelerations: γ ← γ − 2α (J v + Φ_t) − α² Φ, so that J v̇ = γ
/// makes the drift obey Φ̈ + 2α Φ̇ + α² Φ = 0 (critically damped at the rate α, 1/s). s.v holds
/// the stacked velocities and s.rows the rows at the state. On the manifold it changes nothing.
template <typename S>
void add_baumgarte(const S& alpha, ConstraintSolveTpl<S>& s) {
  // The product into the sized scratch first: inside the sum Eigen would evaluate it into a
  // temporary on the heap, once per evaluation.
  s.rate.noalias() = s.rows.J * s.v;
  s.rate += s.rows.phi_t;
  s.rows.gamma -= (S(2) * alpha) * s.rate;
  s.rows.gamma -= (alpha * alpha) * s.rows.phi;
}

/// The joints' length scale ℓ: the largest arm from a body's Br to a joint point, |∂(u·v_P)/∂ω̄|
/// over the length rows of J (1 when every joint sits at its bodies' reference points). Relative
/// violations divide a length row's Φ by it.
template <typename S>
S joint_length_scale(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                     const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) {
  S scale = S(0);
  for (Eigen::Index r = 0; r < J.rows(); ++r) {
    if (!equations.is_length_row(static_cast<int>(r))) continue;
    for (std::size_t b = 0; b + 1 < layout.offsets.size(); ++b) {
      const S arm = J.row(r).template segment<3>(layout.offset(static_cast<int>(b)) + 3).norm();
      if (arm > scale) scale = arm;
    }
  }
  return scale > S(0) ? scale : S(1);
}

/// The largest relative position violation of the rows: |Φ_r| / ℓ for a length row, |Φ_r| for a
/// rotation row (the sine of an angle).
template <typename S>
S relative_position_violation(const ConstraintEquationsTpl<S>& equations,
                              const Eigen::Matrix<S, Eigen::Dynamic, 1>& phi,
                              const S& length_scale) {
  using std::abs;
  S worst = S(0);
  for (Eigen::Index r = 0; r < phi.size(); ++r) {
    const S v = abs(phi(r)) / (equations.is_length_row(static_cast<int>(r)) ? length_scale : S(1));
    if (v > worst) worst = v;
  }
  return worst;
}

/// Newton projection of the positions onto Φ(q, t) = 0 in the mass metric (Hairer, Lubich &
/// Wanner IV.4, Newton with the Jacobian of each iterate). On entry s is factored at the
/// positions; factor_at() evaluates the rows at the current positions into s.rows and factors
/// them (factor_constraints), violation()
/// is the relative position violation of s.rows, apply_increment(δ) adds δ = s.x, the stacked
/// (δp_Br, δφ_B, δq_f), to the positions. Stops when the violation is at most `converged` (a
/// few ε of S: the round-off of Φ itself) or after 20 iterations (far more than quadratic
/// convergence needs from an accepted violation; a far start may first grow before it
/// converges, so a growing iterate does not stop it). s is left factored at the final
/// positions.
template <typename S, typename FactorAt, typename Violation, typename ApplyIncrement>
void project_positions(FactorAt&& factor_at, Violation&& violation,
                       ApplyIncrement&& apply_increment, const S& converged,
                       ConstraintSolveTpl<S>& s) {
  S current = violation();
  for (int iteration = 0; iteration < 20 && current > converged; ++iteration) {
    constraint_correction<S>(s.rows.phi, s);
    apply_increment(s.x);
    factor_at();
    current = violation();
  }
}

/// Per joint, the largest |Φ| of its rows and the largest |J v + Φ_t| of its velocity rows, from
/// the rows and the stacked velocities at a state.
template <typename S>
std::vector<std::array<S, 2>> joint_violations(const ConstraintEquationsTpl<S>& equations,
                                               const ConstraintRowsTpl<S>& rows,
                                               const Eigen::Matrix<S, Eigen::Dynamic, 1>& v) {
  using std::abs;
  const Eigen::Matrix<S, Eigen::Dynamic, 1> rate = rows.J * v + rows.phi_t;
  std::vector<std::array<S, 2>> out(static_cast<std::size_t>(equations.joint_count()),
                                    {S(0), S(0)});
  for (Eigen::Index r = 0; r < rows.phi.size(); ++r) {
    auto& j = out[static_cast<std::size_t>(equations.joint_of_row(static_cast<int>(r)))];
    if (abs(rows.phi(r)) > j[0]) j[0] = abs(rows.phi(r));
    if (abs(rate(r)) > j[1]) j[1] = abs(rate(r));
  }
  return out;
}

/// The multipliers on `rows` that give the generalized constraint force F = −Σ_r λ_r J_rᵀ: the
/// same reactions on another basis of the rows' span (any two independent row sets of the same
/// rank span it), from the normal equations (J_r J_rᵀ) λ = −J_r F. For integrators that carry
/// multipliers of their own rows across a solve that chose others (a restart, rows chosen again
/// in motion). Allocates: those rare paths only.
template <typename S>
Eigen::Matrix<S, Eigen::Dynamic, 1> multipliers_on_rows(
    const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J, const std::vector<int>& rows,
    const Eigen::Matrix<S, Eigen::Dynamic, 1>& force) {
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> J_r(static_cast<Eigen::Index>(rows.size()),
                                                       J.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    J_r.row(static_cast<Eigen::Index>(i)) = J.row(rows[i]);
  }
  return (J_r * J_r.transpose()).ldlt().solve(-(J_r * force));
}

/// The minimum-norm multipliers of all rows (redundant ones included) that give the generalized
/// constraint force F = −J_aᵀ λ_a: λ = argmin |λ| subject to −Jᵀ λ = F (a complete orthogonal
/// decomposition of Jᵀ), at the rank the solve enforced (`rank`, its independent rows' count).
/// The rank is not decided again here: off the configurations where the set-aside rows depend
/// exactly on the others (a solution's drift, ~1e-10), their pivots sit at the drift's size,
/// where a fixed threshold took them for independent and gave a Bricard linkage's rods reactions
/// of 241 N beside a 9.81 N weight; the threshold is the geometric mean of the QR's pivots
/// number rank and rank + 1 instead. Allocates: for outputs, not for evaluations.
template <typename S>
Eigen::Matrix<S, Eigen::Dynamic, 1> minimum_norm_multipliers(
    const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J,
    const Eigen::Matrix<S, Eigen::Dynamic, 1>& force, Eigen::Index rank) {
  using std::abs;
  using std::sqrt;
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  Eigen::CompleteOrthogonalDecomposition<Matrix> cod(J.rows(), J.cols());
  S threshold = S(kRedundantRowTolerance);
  const Eigen::Index pivots = std::min(J.rows(), J.cols());
  if (rank > 0 && rank < pivots) {
    const Eigen::ColPivHouseholderQR<Matrix> qr(J.transpose());
    const auto d = qr.matrixR().diagonal();
    const S largest = abs(d(0));
    if (largest > S(0)) {
      threshold = std::max<S>(sqrt(abs(d(rank - 1)) * abs(d(rank))) / largest,
                              S(16) * std::numeric_limits<S>::epsilon());
    }
  }
  cod.setThreshold(threshold);
  cod.compute(J.transpose());
  return cod.solve(Eigen::Matrix<S, Eigen::Dynamic, 1>(-force));
}

/// Per joint, the force and torque it exerts on its first body (ConstraintEquationsTpl::reaction)
/// from the constrained solve at a state (s.rows and s.force of solve_constrained_accelerations):
/// the minimum-norm multipliers of all rows, then each joint's own rows' generalized force
/// −J_jᵀ λ_j. Allocates: for outputs.
template <typename S>
std::vector<JointReactionTpl<S>> joint_reactions_from_solve(
    const ConstraintEquationsTpl<S>& equations, std::span<const BodyKinematicsTpl<S>> bodies,
    const VelocityLayout& layout, const ConstraintSolveTpl<S>& s) {
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  const Vector lambda =
      minimum_norm_multipliers<S>(s.rows.J, s.force, static_cast<Eigen::Index>(s.active.size()));
  Vector force(layout.size());
  std::vector<JointReactionTpl<S>> out;
  for (int j = 0; j < equations.joint_count(); ++j) {
    const std::array<int, 2> rows = equations.joint_rows(j);
    force.noalias() =
        -s.rows.J.middleRows(rows[0], rows[1]).transpose() * lambda.segment(rows[0], rows[1]);
    out.push_back(equations.reaction(j, bodies, layout, force));
  }
  return out;
}

}  // namespace flexref::core
