#pragma once
/// \file constraint_tracker.hpp
/// The ideal joints' history an integrator carries from one accepted state to the next
/// (docs/decisions.md, "Model, Workspace, tracker"): which rows are in force and what the rows
/// were at the last accepted state. The Model holds what the scene fixes, a Workspace is scratch
/// any evaluation overwrites, and this is the third thing: state of the integration that is
/// neither, owned by the integrator beside its own state (Drake keeps such history in the
/// integrator's context, not in the system).
///
/// - The rows in force are the independent rows chosen at the initial configuration
///   (Model::independent_rows), chosen again in motion where they become ill-conditioned
///   (core/row_selection_tpl.hpp), with the pivot ratio they were chosen at.
/// - The rows at the last accepted state are what the next solves compare their orientation
///   with: a singular configuration passed in between turns it (core/orientation_test_tpl.hpp).
///
/// Every evaluation reads a tracker (const): it enforces the tracker's rows, or rows it chooses
/// again for itself where they have become ill-conditioned, and hands its multipliers out with
/// the rows they belong to (core/joint_multipliers_tpl.hpp). Only Model::advance_tracker changes
/// a tracker, at a state the integrator accepted (a step, an output, a restart): a trial point a
/// solver rejects never moves it.
#include <Eigen/Core>
#include <vector>

#include "core/constraint_jacobian_tpl.hpp"
#include "core/row_gram_tpl.hpp"

namespace flexref::core {

/// How far an accepted state moves a tracker (Model::advance_tracker).
enum class TrackerAdvance {
  /// The rows in force chosen again where they became ill-conditioned, the test for a singular
  /// configuration passed since the last accepted state, and the rows at this state as the next
  /// solves' reference.
  kFull,
  /// The same without the orientation test: outputs at any spacing, or a state the evaluations
  /// of the step that reached it have tested against the accepted state already.
  kWithoutOrientation,
  /// Only the reference of the orientation test (the rows at this state; no factorization), the
  /// rows in force and their ratio kept: where no evaluation since the tracker last moved had to
  /// choose its rows again (JointMultipliers::rows_chosen).
  kReference,
  /// As kFull, the rows chosen again at this state whatever their conditioning here: where a
  /// solve since the tracker last moved found them ill-conditioned at its own state (a trial
  /// point further on, where their conditioning was falling), so that the integration goes on
  /// with the best-conditioned rows of the accepted state rather than with rows its next
  /// evaluations would each choose again.
  kChooseRows,
};

template <typename S>
struct ConstraintTrackerTpl {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  /// The independent rows in force (ascending indices into the joints' rows).
  std::vector<int> rows;
  /// The pivot ratio of J M⁻¹ Jᵀ over `rows` when they were chosen (the reference of
  /// kReselectPivotFall); 0: not yet factored, the first solve's ratio is taken.
  S selection_ratio = S(0);
  /// All rows' J (m × N, by its body blocks) at the last accepted state, its time, and whether
  /// there is one.
  ConstraintJacobianTpl<S> J_accepted;
  double accepted_time = 0.0;
  bool has_accepted = false;

  /// Multipliers λ of the rows `from` carried over to the tracker's rows at its accepted state:
  /// the same generalized reaction F = −J_fromᵀ λ (any two independent row sets of one rank span
  /// the same space there), from the normal equations (J_r J_rᵀ) λ_r = −J_r F. For an integrator
  /// whose own unknowns are multipliers when the tracker chose other rows (genalpha). Allocates.
  Vector carry(const Vector& lambda, const std::vector<int>& from) const {
    Vector force = Vector::Zero(J_accepted.cols());
    for (std::size_t i = 0; i < from.size(); ++i) {
      J_accepted.add_row_transpose(from[i], S(-lambda(static_cast<Eigen::Index>(i))), force);
    }
    return multipliers_on_rows<S>(J_accepted, rows, force);
  }
};
using ConstraintTracker = ConstraintTrackerTpl<double>;

}  // namespace flexref::core
