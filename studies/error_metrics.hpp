#pragma once
/// \file error_metrics.hpp
/// Error of a trajectory against a reference on the same output times (docs/design/schemes.md,
/// "Error metrics"): per body the position of the frame origin |x − x_ref|, the geodesic
/// rotation angle |log(A_refᵀ A)|, the velocity and angular-velocity errors; per tracked point
/// its position error; per flexible body the modal-coordinate error max_i |q_i − q_i,ref|. Each
/// is reduced over time to L∞ (max), RMS and final value.
#include <string>
#include <vector>

#include "studies/trajectory_table.hpp"

namespace flexref::studies {

struct ErrorNorms {
  double linf = 0.0;
  double rms = 0.0;
  double final = 0.0;
};

struct QuantityError {
  std::string name;  ///< e.g. "book.rotation", "book.velocity", "book.corner" (a point)
  std::string unit;  ///< "m", "rad", "m/s", "rad/s"
  ErrorNorms norms;
};

struct ComparisonReport {
  std::vector<QuantityError> quantities;
  double max_rotation_linf = 0.0;  ///< max over bodies, rad
  double max_point_linf = 0.0;     ///< max over tracked points, m
  double max_modal_linf = 0.0;     ///< max over flexible bodies of max_i |q_i − q_i,ref|
  /// Named contacts' final wear work: max over contacts of |W − W_ref|/|W_ref| at the last
  /// output (|W| when W_ref = 0); −1 when the tables have no `C.wear_work` column.
  double max_wear_relative = -1.0;
  /// Default study metric: L∞ geodesic rotation angle + L∞ tracked-point position (max over
  /// bodies and points). Named "rotation+points".
  double default_metric() const { return max_rotation_linf + max_point_linf; }
};

/// Compares two tables with the same columns on the same times (to 1e-9 relative); throws
/// std::invalid_argument naming the first mismatch.
ComparisonReport compare_trajectories(const TrajectoryTable& run, const TrajectoryTable& reference);

/// The metrics a study may name: "rotation+points" (default), "rotation", "points", "modes"
/// (L∞ over time of max_i |q_i − q_i,ref| over the flexible bodies' modal coordinates),
/// "position", "velocity", "angular_velocity", "wear" (max_wear_relative; the scene must have a
/// named contact, docs/output.md "Wear outputs"). Throws std::invalid_argument otherwise.
double metric_value(const ComparisonReport& report, const std::string& metric);

}  // namespace flexref::studies
