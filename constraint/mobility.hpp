#pragma once
/// \file mobility.hpp
/// The degrees of freedom of a model with ideal joints, by counting and in fact, and the rows the
/// model found redundant (docs/joints.md, "Redundant constraints"): what `flexref check` prints.
///
/// By counting (Grübler–Kutzbach in 3D): the bodies' coordinates minus the joints' rows. In fact:
/// the coordinates minus the rank of the rows' Jacobian at the initial configuration, the number
/// of independent rows core::Model keeps (core::independent_rows, a column-pivoted QR of Jᵀ). The
/// rows it leaves out are redundant: their multipliers are not determined by the motion, and the
/// model reports the minimum-norm reactions.
#include <string>
#include <vector>

#include "constraint/ideal_joint.hpp"
#include "core/model.hpp"

namespace flexref::constraint {

/// A constraint row the model left out as redundant.
struct RedundantRow {
  int row = 0;        ///< index among all rows
  std::string joint;  ///< the joint's name
  int joint_row = 0;  ///< index among the joint's rows
  std::string label;  ///< what the row holds (row_label)
};

struct Mobility {
  int coordinates = 0;  ///< Σ over the bodies: 6 (free), 3 (pivot), 0 (prescribed) + modes
  int rows = 0;         ///< constraint rows of all ideal joints
  int rank = 0;         ///< independent rows at the initial configuration
  int by_counting() const { return coordinates - rows; }
  int in_fact() const { return coordinates - rank; }
  std::vector<RedundantRow> redundant;
};

/// The model's mobility; without ideal joints rows = rank = 0 and nothing is redundant.
Mobility mobility(const core::Model& model);

/// What row k (0-based) of a joint of this type holds, in the order IdealJointsTpl evaluates
/// them, e.g. "point y", "axis Z_b.Y_a = 0", "drive". Throws std::out_of_range past the joint's
/// rows.
std::string row_label(JointType type, bool driven, int k);

}  // namespace flexref::constraint
