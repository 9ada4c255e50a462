#pragma once
/// \file orientation_test_tpl.hpp
/// The test for a singular configuration passed between two solves (docs/joints.md, "Singular
/// configurations"): A's pivot ratio falls as the square of the distance to a dead point and
/// flags only evaluations within ~1e-6 of it, which a solver's steps usually jump over; the
/// rows' orientation, det(J_a,accepted M⁻¹ J_aᵀ), changes sign where a singular value of J passes
/// through zero between the last accepted state (the tracker's, core/constraint_tracker.hpp)
/// and the configuration solved now.
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "core/row_selection_tpl.hpp"

namespace flexref::core {

/// Cosine of the largest angle the active rows may turn through between two solves for the
/// orientation test to apply (rows_turned_little): 0.5 rad. The test reads the sign of
/// det(J_a,accepted M⁻¹ J_aᵀ), which a dead point crossed flips; rows that turned by more can
/// flip it without one (an explicit solver's long steps on a driven hinge). The crossings the
/// test exists for are stepped over by a few hundredths of a radian (docs/joints.md).
inline constexpr double kOrientationTestCosine = 0.87758256189037276;  // cos 0.5

/// True when the active rows kept their orientation since the accepted rows J_accepted (all
/// rows, by J's blocks): det(J_a,accepted M⁻¹ J_aᵀ) > 0. Both are bases of the rows' span; away
/// from singular configurations and for the small state changes between a solver's evaluations
/// the product is close to A, symmetric positive definite. When a configuration where the rows
/// lose rank lies between the two (a four-bar's change point, stepped over), a singular value of
/// J changes sign and the determinant with it. s factored at the current rows (s.Y = M⁻¹ J_aᵀ).
/// The product has A's pattern; its sparse LU in A's pivot order without pivoting
/// (core/sparse_ldl_tpl.hpp) is stable for a matrix this close to A, and a symmetric
/// permutation leaves the determinant's sign as it is: the sign is the product of D's.
template <typename S>
bool kept_orientation(const ConstraintJacobianTpl<S>& J_accepted, ConstraintSolveTpl<S>& s) {
  const auto m = static_cast<Eigen::Index>(s.active.size());
  if (m == 0) return true;
  for (int p = 0; p < s.schur.nonzeros(); ++p) {
    s.schur.entries(p, J_accepted.all_values(), s.Y.all_values(), s.crossing_upper(p),
                    s.crossing_lower(p));
  }
  if (!s.crossing_lu.factor_unsymmetric(s.crossing_upper, s.crossing_lower)) return false;
  int sign = 1;
  const auto& d = s.crossing_lu.d();
  for (Eigen::Index k = 0; k < m; ++k) {
    if (!(d(k) != S(0))) return false;
    if (d(k) < S(0)) sign = -sign;
  }
  return sign > 0;
}

/// Throws SingularConfigurationError for a singular configuration passed between two solves, at
/// t0 and t1 (kept_orientation): the joint of the active row with the smallest pivot of A's
/// LDLᵀ (in its fill-reducing order) at t1, the row nearest to dependence on the others.
template <typename S>
[[noreturn]] void throw_singular_between(const ConstraintEquationsTpl<S>& equations,
                                         const ConstraintSolveTpl<S>& s, double t0, double t1) {
  using std::abs;
  const auto& d = s.ldlt.d();
  Eigen::Index smallest = 0;
  for (Eigen::Index k = 1; k < d.size(); ++k) {
    if (abs(d(k)) < abs(d(smallest))) smallest = k;
  }
  const int row = d.size() > 0 ? s.schur.order[static_cast<std::size_t>(smallest)] : 0;
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

/// Whether the active rows turned through less than kOrientationTestCosine's angle since the
/// accepted rows (each row's direction on the bodies it acts on, accepted against current):
/// where they turned more, the orientation test is not conclusive.
template <typename S>
bool rows_turned_little(const ConstraintJacobianTpl<S>& J_accepted,
                        const ConstraintSolveTpl<S>& s) {
  for (const int row : s.active) {
    S dot = S(0), previous = S(0), current = S(0);
    for (int k = 0; k < 2; ++k) {
      if (J_accepted.slot(row, k).body < 0) continue;
      const auto a = J_accepted.values(row, k);
      const auto b = s.rows.jacobian.values(row, k);
      const int width = J_accepted.slot(row, k).width;
      dot += block_dot<S>(a.data(), b.data(), width);
      previous += block_dot<S>(a.data(), a.data(), width);
      current += block_dot<S>(b.data(), b.data(), width);
    }
    using std::sqrt;
    if (dot < S(kOrientationTestCosine) * sqrt(previous * current)) return false;
  }
  return true;
}

/// The singular-configuration test between the accepted rows (J_accepted at t_accepted) and s,
/// factored at t. Where the active rows alone turned — they passed a configuration where they
/// are dependent while all rows kept their rank — rows chosen at the current configuration keep
/// the orientation (s.active then holds them); otherwise the mechanism passed a singular
/// configuration between the two: throws SingularConfigurationError.
template <typename S, typename ApplyInverseMass>
void check_orientation(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                       ApplyInverseMass&& apply_inverse_mass,
                       const ConstraintJacobianTpl<S>& J_accepted, double t_accepted, double t,
                       ConstraintSolveTpl<S>& s) {
  // The test assumes the small changes between a solver's evaluations; where the rows turned
  // through more (an explicit solver's long steps on a smooth driven motion), it would read the
  // turn for a crossing: it is skipped.
  if (!rows_turned_little(J_accepted, s) || kept_orientation(J_accepted, s)) {
    return;
  }
  s.rows_chosen = true;
  std::vector<int> rows = independent_rows<S>(s.rows.jacobian);
  rows.resize(std::min(rows.size(), s.active.size()));
  if (rows.size() == s.active.size() && rows != s.active) {
    s.active = std::move(rows);
    if (!factor_constraints(equations, layout, apply_inverse_mass, s)) {
      throw_singular(equations, s, t);
    }
  }
  if (!kept_orientation(J_accepted, s)) throw_singular_between(equations, s, t_accepted, t);
}

}  // namespace flexref::core
