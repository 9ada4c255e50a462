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
///
/// Everything here is sparse (docs/decisions.md, "Constrained systems at scale"): J by its body
/// blocks (core/constraint_jacobian_tpl.hpp), Y = M⁻¹ J_aᵀ by the same blocks, A by the pattern
/// of rows sharing a body in a fill-reducing order (core/schur_pattern_tpl.hpp), factored by a
/// sparse LDLᵀ (core/sparse_ldl_tpl.hpp) whose symbolic phase runs once per row set: an
/// evaluation costs O(m) for a chain, not O(m³).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/constraint_equations.hpp"
#include "core/schur_pattern_tpl.hpp"
#include "core/sparse_ldl_tpl.hpp"

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

/// Scratch of one constrained evaluation, sized once (allocation-free evaluations; the pattern
/// of A is built again only where the rows enforced change: setup and the rare evaluations that
/// choose rows again). It holds nothing an evaluation reads from an earlier one: `active` and
/// `selection_ratio` start from the caller's tracker at every evaluation
/// (core/constraint_tracker.hpp) and end as the rows this evaluation enforced and the
/// multipliers' rows (core/joint_multipliers_tpl.hpp).
template <typename S>
struct ConstraintSolveTpl {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  ConstraintRowsTpl<S> rows;
  std::vector<int> active;  ///< the rows this evaluation enforces (indices into rows)
  /// Y = M⁻¹ J_aᵀ by J's blocks: row r's blocks hold M_b⁻¹ J_r,bᵀ (active rows only).
  ConstraintJacobianTpl<S> Y;
  SchurPattern schur;    ///< A's pattern for the rows it was built for
  Vector A;              ///< A's upper triangle by schur's entries
  SparseLdlTpl<S> ldlt;  ///< A = L D Lᵀ in schur's pivot order
  Vector rhs;            ///< m_a
  Vector lambda;         ///< m_a: the multipliers of the active rows
  Vector pivoted;        ///< m_a: a right-hand side in the pivot order
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
  /// J_a,accepted M⁻¹ J_aᵀ (the orientation test) by schur's entries, upper and lower, and its
  /// L D W̃ᵀ.
  Vector crossing_upper, crossing_lower;
  SparseLdlTpl<S> crossing_lu;

  ConstraintSolveTpl() = default;
  ConstraintSolveTpl(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                     std::vector<int> active_rows) {
    const int rows_count = equations.row_count();
    rows.resize_sparse(rows_count);
    equations.prepare_rows(layout, rows);
    Y = rows.jacobian;
    active = std::move(active_rows);
    const auto m = static_cast<Eigen::Index>(active.size());
    const Eigen::Index n = layout.size();
    rhs = Vector::Zero(m);
    lambda = Vector::Zero(m);
    pivoted = Vector::Zero(m);
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
    prepare_pattern();
  }

  /// A's pattern and factorizations' symbolic phase for `active`, unless they are for it.
  /// Allocates only then.
  void prepare_pattern() {
    if (schur.is_for(active)) return;
    schur.build(active, rows.jacobian);
    const int m = static_cast<int>(active.size());
    ldlt.analyze(m, schur.column_start, schur.row_index);
    crossing_lu.analyze(m, schur.column_start, schur.row_index);
    A = Vector::Zero(schur.nonzeros());
    crossing_upper = Vector::Zero(schur.nonzeros());
    crossing_lower = Vector::Zero(schur.nonzeros());
    if (rhs.size() != m) {
      rhs = Vector::Zero(m);
      lambda = Vector::Zero(m);
      pivoted = Vector::Zero(m);
    }
  }

  /// lambda ← A⁻¹ rhs (both by active index), A factored.
  void solve_schur() {
    const auto m = static_cast<Eigen::Index>(active.size());
    for (Eigen::Index k = 0; k < m; ++k) pivoted(k) = rhs(schur.order[static_cast<std::size_t>(k)]);
    ldlt.solve_in_place(pivoted);
    for (Eigen::Index k = 0; k < m; ++k)
      lambda(schur.order[static_cast<std::size_t>(k)]) = pivoted(k);
  }

  /// x ← x − Y λ (the active rows' blocks).
  void subtract_y_lambda() {
    for (std::size_t i = 0; i < active.size(); ++i) {
      Y.add_row_transpose(active[i], S(-lambda(static_cast<Eigen::Index>(i))), x);
    }
  }
};

using ConstraintSolve = ConstraintSolveTpl<double>;

/// True for the bodies[k] a row acts on that count once: not the ground (−1), not a repeat.
inline bool distinct_body(const std::array<int, 2>& bodies, std::size_t k) {
  return bodies[k] >= 0 && !(k == 1 && bodies[1] == bodies[0]);
}

/// Y = M⁻¹ J_aᵀ, A = J_a Y and A's LDLᵀ for the active rows of s.rows. apply_inverse_mass(b,
/// rhs, out) writes M_b⁻¹ rhs into out (body b's block width; the rows the body's motion fixes
/// stay zero). Returns false (s.pivot_ratio set) when A is singular by kSingularPivotRatio.
template <typename S, typename ApplyInverseMass>
bool factor_constraints(const ConstraintEquationsTpl<S>&, const VelocityLayout&,
                        ApplyInverseMass&& apply_inverse_mass, ConstraintSolveTpl<S>& s) {
  using std::abs;
  s.prepare_pattern();
  const auto m = static_cast<Eigen::Index>(s.active.size());
  for (Eigen::Index i = 0; i < m; ++i) {
    const int row = s.active[static_cast<std::size_t>(i)];
    for (int k = 0; k < 2; ++k) {
      const auto& slot = s.rows.jacobian.slot(row, k);
      if (slot.body < 0) continue;
      s.column.head(slot.width) = s.rows.jacobian.values(row, k);
      apply_inverse_mass(slot.body, s.column.head(slot.width), s.out.head(slot.width));
      s.Y.values(row, k) = s.out.head(slot.width);
    }
  }
  // A_ik = Σ over the bodies rows i and k share of J_i,b · Y_b,k (schur's entries).
  for (int p = 0; p < s.schur.nonzeros(); ++p) {
    s.A(p) = s.schur.entry(p, s.rows.jacobian.all_values(), s.Y.all_values(), false);
  }
  if (m == 0) {
    s.pivot_ratio = S(1);
    return true;
  }
  const bool factored = s.ldlt.factor_symmetric(s.A);
  const auto& d = s.ldlt.d();
  S smallest = abs(d(0));
  S largest = abs(d(0));
  for (Eigen::Index k = 1; k < m; ++k) {
    smallest = std::min<S>(smallest, abs(d(k)));
    largest = std::max<S>(largest, abs(d(k)));
  }
  s.pivot_ratio = largest > S(0) ? S(smallest / largest) : S(0);
  return factored && s.pivot_ratio > S(kSingularPivotRatio);
}

}  // namespace flexref::core
