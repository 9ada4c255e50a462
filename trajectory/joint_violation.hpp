#pragma once
/// \file joint_violation.hpp
/// How far a run is off its scene's ideal joints, measured from its positions (docs/external.md,
/// "Joints"): the joints' position rows Φ(q, t) (constraint/ideal_joints.hpp, through the
/// model's own constraint equations) evaluated at the bodies' poses the run wrote, B.x..B.z and
/// B.e0..B.e3 (and a flexible body's B.q1.. where a joint sits at one of its nodes), at every
/// row. A run that leaves a joint — an engine that dropped it, a soft or drifting constraint —
/// is then seen whatever columns it writes of its own; its `J.phi` columns are not read.
///
/// A run is judged **off its joints** when a joint's violation is not small against the run's
/// own error at that joint (judge_joints): a violation that does not shrink with the step
/// (a soft constraint's floor, a dropped joint) is part of the error an order is fitted from,
/// and a level whose error is mostly such a violation measures another system. And a run that
/// lacks the pose columns of a jointed body cannot be checked: it is judged off its joints too.
#include <limits>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {

/// One ideal joint's largest violation over a run's rows.
struct JointViolation {
  std::string name;
  double length = 0.0;  ///< largest |Φ| of its length rows (point, slide, distance), m
  double angle = 0.0;   ///< largest |Φ| of its rotation rows (the sine of an angle error)
  double time = 0.0;    ///< the row time of the larger of the two
  /// false when the run lacks a column the joint needs (missing names them).
  bool measured = true;
  std::string missing;
  /// The largest |Φ| of all its rows, as the `J.phi` column reports it (m or rad).
  double value() const { return std::max(length, angle); }
};

/// Every ideal joint of the model (in its order), measured in a table whose values compare_run or
/// checked_reference accepted. Empty for a model without ideal joints.
std::vector<JointViolation> measure_joints(const core::Model& model, const TrajectoryTable& table);

/// A violation not larger than this fraction of the run's own error at the joint is small.
/// Derivation: a part δ of a level's error e that does not shrink with the step (a violation's
/// floor) biases the order measured from that level and a finer one by −log2(1 − δ/e) at
/// most (the finer level's error shrinks by 2^p everywhere but in δ); kept below 0.1, the
/// precision an order is quoted to, δ/e ≤ 1 − 2^(−0.1) = 0.067. A joint's violation is a
/// separation of its two ends that the reference does not have: at least that much of the run's
/// error at the joint.
inline const double kJointViolationFraction = 1.0 - std::exp2(-0.1);

/// The verdict on a run's joints: off them when a joint's violation beyond the reference's own
/// (the reference drifts too, within its estimated error) exceeds kJointViolationFraction of the
/// run's error at the joint, or when a joint cannot be measured. The error at a joint is that of
/// its bodies' poses (the comparison's B.position and B.rotation L∞ errors, e_p and e_r), in
/// the units of the joint's rows: for length rows Σ over its bodies of e_p + ρ e_r (ρ the
/// body's radius: the largest distance of its centre of mass, tracked points and joint points
/// from its origin, so ρ e_r bounds how far its attitude error moves its points), for rotation
/// rows Σ e_r.
struct JointVerdict {
  bool off = false;
  /// Why, naming each joint off its manifold with its violation and its error scale, or the
  /// columns a joint needs; empty when on.
  std::string why;
};

/// `noise`: the reference's estimated error (0 when unknown); a violation within it is not
/// measured, whatever the run's error (a level that close to the reference is uncertified).
JointVerdict judge_joints(const core::Model& model, const std::vector<JointViolation>& run,
                          const std::vector<JointViolation>& reference,
                          const ComparisonReport& report, double noise = 0.0);

/// "O 1.2e-03 m, 3.4e-05 rad (t = 0.25)": one joint's line for messages and tables.
std::string describe_violation(const JointViolation& joint);

}  // namespace flexref::trajectory
