#pragma once
/// \file constrained_solve_tpl.hpp
/// The multipliers of holonomic constraints and the constrained accelerations of one evaluation,
/// written once for any scalar type S (core::Model in double, the extended and quad references in
/// S), the advance of a tracker at an accepted state, and the corrections that project onto the
/// constraint manifold. docs/design/model.md, "Ideal joints", index-1 form:
///
///   A λ = J_a M⁻¹ Q − γ_a,   A = J_a M⁻¹ J_aᵀ   (core/schur_complement_tpl.hpp),
///   v̇ = M⁻¹ Q − M⁻¹ J_aᵀ λ,
///
/// over the rows the caller's tracker holds (core/constraint_tracker.hpp), chosen again for the
/// evaluation where they have become ill-conditioned (core/row_selection_tpl.hpp) and tested
/// for a singular configuration passed since the tracker's accepted state
/// (core/orientation_test_tpl.hpp). An evaluation reads the tracker and never changes it;
/// advance_tracker, at a state the integrator accepted, does.
#include <Eigen/Core>
#include <limits>

#include "core/constraint_tracker.hpp"
#include "core/orientation_test_tpl.hpp"

namespace flexref::core {

/// The rows an evaluation enforces at the configuration whose rows s.rows holds, factored: the
/// tracker's rows, chosen again where they became ill-conditioned (choose_rows), and with
/// `orientation` and an accepted state in the tracker the test for a singular configuration
/// passed since (check_orientation); with `choose` the rows chosen again at this state whatever
/// their conditioning. s.active and s.selection_ratio end as the rows enforced and the ratio they
/// were chosen at. Throws SingularConfigurationError (t names the time).
template <typename S, typename ApplyInverseMass>
void factor_tracked_rows(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                         ApplyInverseMass&& apply_inverse_mass,
                         const ConstraintTrackerTpl<S>& tracker, double t, bool orientation,
                         ConstraintSolveTpl<S>& s, bool choose = false) {
  s.active = tracker.rows;  // the same count every time: the scratch's capacity, no allocation
  // `choose`: a reference no ratio reaches makes choose_rows choose them at this state.
  s.selection_ratio = choose ? std::numeric_limits<S>::infinity() : tracker.selection_ratio;
  s.rows_chosen = false;
  if (!choose_rows(equations, layout, apply_inverse_mass, s)) throw_singular(equations, s, t);
  if (orientation && tracker.has_accepted) {
    check_orientation(equations, layout, apply_inverse_mass, tracker.J_accepted,
                      tracker.accepted_time, t, s);
  }
}

/// Constrained accelerations: s.x holds the free accelerations M⁻¹ Q on entry (stacked, body
/// blocks as in layout) and the constrained ones on exit; s.rows evaluated at the state; the
/// rows enforced in s.active, λ of them in s.lambda and the generalized constraint force
/// −J_aᵀ λ in s.force. Throws SingularConfigurationError at a singular configuration (t names
/// the time).
template <typename S, typename ApplyInverseMass>
void solve_constrained_accelerations(const ConstraintEquationsTpl<S>& equations,
                                     const VelocityLayout& layout,
                                     ApplyInverseMass&& apply_inverse_mass, double t,
                                     const ConstraintTrackerTpl<S>& tracker,
                                     ConstraintSolveTpl<S>& s) {
  factor_tracked_rows(equations, layout, apply_inverse_mass, tracker, t, true, s);
  const auto m = static_cast<Eigen::Index>(s.active.size());
  // A λ = J_a x_free − γ_a
  for (Eigen::Index i = 0; i < m; ++i) {
    const int row = s.active[static_cast<std::size_t>(i)];
    s.rhs(i) = s.rows.jacobian.row_dot(row, s.x) - s.rows.gamma(row);
  }
  s.solve_schur();
  // v̇ = x_free − Y λ;  F = −J_aᵀ λ
  s.subtract_y_lambda();
  s.force.setZero();
  for (Eigen::Index i = 0; i < m; ++i) {
    s.rows.jacobian.add_row_transpose(s.active[static_cast<std::size_t>(i)], S(-s.lambda(i)),
                                      s.force);
  }
}

/// The rows s.rows holds, at the accepted state at t, as the tracker's reference for the next
/// solves' orientation test (the rows in force and their ratio as they are).
template <typename S>
void move_reference(double t, const ConstraintSolveTpl<S>& s, ConstraintTrackerTpl<S>& tracker) {
  tracker.J_accepted = s.rows.jacobian;
  tracker.accepted_time = t;
  tracker.has_accepted = true;
}

/// The tracker moved to an accepted state at t whose rows s.rows holds: the rows in force chosen
/// again where they became ill-conditioned (with `choose`, whatever their conditioning), the
/// test for a singular configuration passed since
/// its last accepted state (with `orientation`), then that state's rows kept as the next
/// solves' reference. Throws SingularConfigurationError, leaving the tracker as it was.
template <typename S, typename ApplyInverseMass>
void advance_tracker(const ConstraintEquationsTpl<S>& equations, const VelocityLayout& layout,
                     ApplyInverseMass&& apply_inverse_mass, double t, bool orientation, bool choose,
                     ConstraintTrackerTpl<S>& tracker, ConstraintSolveTpl<S>& s) {
  factor_tracked_rows(equations, layout, apply_inverse_mass, tracker, t, orientation, s, choose);
  tracker.rows = s.active;
  tracker.selection_ratio = s.selection_ratio;
  move_reference(t, s, tracker);
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
  s.solve_schur();
  s.x.setZero();
  s.subtract_y_lambda();
}

/// Baumgarte stabilization of the accelerations: γ ← γ − 2α (J v + Φ_t) − α² Φ, so that J v̇ = γ
/// makes the drift obey Φ̈ + 2α Φ̇ + α² Φ = 0 (critically damped at the rate α, 1/s). s.v holds
/// the stacked velocities and s.rows the rows at the state. On the manifold it changes nothing.
template <typename S>
void add_baumgarte(const S& alpha, ConstraintSolveTpl<S>& s) {
  s.rows.jacobian.multiply(s.v, s.rate);
  s.rate += s.rows.phi_t;
  s.rows.gamma -= (S(2) * alpha) * s.rate;
  s.rows.gamma -= (alpha * alpha) * s.rows.phi;
}

}  // namespace flexref::core
