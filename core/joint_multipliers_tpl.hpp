#pragma once
/// \file joint_multipliers_tpl.hpp
/// The ideal joints' multipliers of an evaluation, always with the rows they belong to: an
/// evaluation enforces its tracker's rows or rows it chose again for itself
/// (core/constrained_solve_tpl.hpp), so λ read against any other row set would pair one row's
/// multiplier with another's reaction. Here too the same reactions on another basis of the rows'
/// span and per joint (the minimum-norm multipliers of all rows, the redundant ones included).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "core/row_selection_tpl.hpp"

namespace flexref::core {

/// The multipliers of the last constrained evaluation on a workspace's scratch, with the rows
/// they belong to (Model::joint_multipliers): λ_i is the multiplier of row rows()[i]. A view:
/// valid until the workspace's next evaluation.
template <typename S>
class JointMultipliersTpl {
 public:
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  explicit JointMultipliersTpl(const ConstraintSolveTpl<S>& solve) : solve_(&solve) {}
  /// The rows the multipliers belong to (the evaluation's: its tracker's, or chosen again).
  const std::vector<int>& rows() const { return solve_->active; }
  /// λ of rows(), M v̇ + J_rowsᵀ λ = Q.
  const Vector& lambda() const { return solve_->lambda; }
  /// The stacked generalized constraint force −J_rowsᵀ λ (basis-independent: the same whatever
  /// rows enforce the joints).
  const Vector& force() const { return solve_->force; }
  /// All rows' J at the evaluated state (m × N) by its body blocks.
  const ConstraintJacobianTpl<S>& jacobian() const { return solve_->rows.jacobian; }
  /// The same dense (for tests and rare paths: allocates).
  Matrix J() const { return solve_->rows.jacobian.dense(); }
  /// Whether the solve chose its rows again at its state (its tracker's had become
  /// ill-conditioned there): a hint to the integrator that its tracker is due to move.
  bool rows_chosen() const { return solve_->rows_chosen; }
  /// The same reactions as multipliers of other rows `target` (multipliers_on_rows); λ itself
  /// where target are rows(). Allocates.
  Vector on_rows(const std::vector<int>& target) const {
    return multipliers_on_rows<S>(solve_->rows.jacobian, target, solve_->force);
  }

 private:
  const ConstraintSolveTpl<S>* solve_;
};
using JointMultipliers = JointMultipliersTpl<double>;

/// The minimum-norm multipliers of all rows (redundant ones included) that give the generalized
/// constraint force F = −J_aᵀ λ_a: λ = argmin |λ| subject to −Jᵀ λ = F (a complete orthogonal
/// decomposition of Jᵀ), at the rank the solve enforced (`rank`, its independent rows' count).
/// The rank is not decided again here: off the configurations where the set-aside rows depend
/// exactly on the others (a solution's drift, ~1e-10), their pivots sit at the drift's size,
/// where a fixed threshold takes them for independent and gives reactions far beyond the loads
/// (docs/joints.md, "Reactions"); the threshold is the geometric mean of the QR's pivots number
/// rank and rank + 1 instead. Allocates: for outputs, not for evaluations.
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
/// from the constrained solve at a state (the multipliers of solve_constrained_accelerations):
/// the minimum-norm multipliers of all rows, then each joint's own rows' generalized force
/// −J_jᵀ λ_j. Where the solve enforced every row (no redundant row), those are its own λ (−Jᵀ λ
/// = F has one solution), and each joint's force is gathered on its bodies' blocks only: linear
/// in the rows. Otherwise the complete orthogonal decomposition, dense. Allocates: for outputs.
template <typename S>
std::vector<JointReactionTpl<S>> joint_reactions_from_solve(
    const ConstraintEquationsTpl<S>& equations, std::span<const BodyKinematicsTpl<S>> bodies,
    const VelocityLayout& layout, const JointMultipliersTpl<S>& multipliers) {
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  const ConstraintJacobianTpl<S>& J = multipliers.jacobian();
  const auto m = static_cast<Eigen::Index>(J.rows());
  Vector lambda = Vector::Zero(m);
  if (static_cast<Eigen::Index>(multipliers.rows().size()) == m) {
    for (std::size_t i = 0; i < multipliers.rows().size(); ++i) {
      lambda(multipliers.rows()[i]) = multipliers.lambda()(static_cast<Eigen::Index>(i));
    }
  } else {
    lambda = minimum_norm_multipliers<S>(J.dense(), multipliers.force(),
                                         static_cast<Eigen::Index>(multipliers.rows().size()));
  }
  Vector force = Vector::Zero(layout.size());
  std::vector<JointReactionTpl<S>> out;
  for (int j = 0; j < equations.joint_count(); ++j) {
    const std::array<int, 2> rows = equations.joint_rows(j);
    for (int r = rows[0]; r < rows[0] + rows[1]; ++r) {
      for (int k = 0; k < 2; ++k) {
        const auto& slot = J.slot(r, k);
        if (slot.body >= 0) force.segment(slot.offset, slot.width).setZero();
      }
    }
    for (int r = rows[0]; r < rows[0] + rows[1]; ++r) J.add_row_transpose(r, S(-lambda(r)), force);
    out.push_back(equations.reaction(j, bodies, layout, force));
  }
  return out;
}

}  // namespace flexref::core
