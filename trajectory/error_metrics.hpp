#pragma once
/// \file error_metrics.hpp
/// Error of a trajectory against a reference on the same output times (docs/design/schemes.md,
/// "Error metrics"): per body the position of the frame origin |x − x_ref|, the geodesic
/// rotation angle |log(A_refᵀ A)|, the velocity and angular-velocity errors; per tracked point
/// its position error; per flexible body the modal-coordinate error max_i |q_i − q_i,ref|. Each
/// is reduced over time to L∞ (max), RMS and final value.
///
/// Quantities are found by column name, not position: a body B is measured in position when
/// the table has `B.x, B.y, B.z`, in rotation when it has `B.e0 … B.e3`, and so on; a table
/// with a subset of the standard columns (docs/external.md) is measured in what it has. A
/// metric that finds nothing to measure is an error, never 0.
#include <limits>
#include <string>
#include <vector>

#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {

struct ErrorNorms {
  double linf = 0.0;
  double rms = 0.0;
  double final = 0.0;
};

struct QuantityError {
  std::string name;  ///< e.g. "book.rotation", "book.velocity", "book.corner" (a point)
  std::string unit;  ///< "m", "rad", "m/s", "rad/s"
  /// "position", "rotation", "velocity", "angular_velocity", "point", "modes",
  /// "reaction_force", "reaction_torque" or "violation" (an ideal joint's)
  std::string kind;
  ErrorNorms norms;
  double linf_time = 0.0;            ///< an output time where the L∞ value is reached
  std::vector<std::string> columns;  ///< the columns this quantity measures
  /// The largest value the error can take while the run stays on the reference's range (see
  /// kSaturationFraction): π for a rotation (the geodesic angle), the reference's extent for a
  /// position, point, velocity or angular velocity (twice the largest distance of its values
  /// from the centre of their bounding box, ≥ their diameter), the largest range of a modal
  /// coordinate for the modes; +∞ where there is none: a relative wear error, or a quantity the
  /// reference holds constant (extent 0).
  double bound = std::numeric_limits<double>::infinity();
};

/// A level whose error reaches this fraction of its quantity's bound is "saturated": it
/// measures how far the run is from the reference's range, not the scheme's order, and is left
/// out of an order fit (docs/decisions.md, "Saturated levels"). Derivation: a point at distance
/// r from an accurate centre, turned by a wrong angle δ, is off by the chord 2r sin(δ/2), and
/// its bound is the extent 2r; the order measured between a level at e = B sin x and its
/// finer neighbour of a p-th order scheme is biased by about p (1 − x cot x). At e = B/3 that is
/// 0.04 for p = 2, below the 0.1 an order is quoted to; beyond it the bias grows quickly (0.09
/// at B/2, 0.2 at 0.7 B) while an unrelated motion sits at 0.7 of the bound (the mean angle
/// between two random rotations, π/2 + 2/π, is 0.70 π). The geodesic angle itself is exact
/// below π but its L∞ over time is capped there, so the same fraction is used for rotations.
inline constexpr double kSaturationFraction = 1.0 / 3.0;

/// A quantity whose extent in the reference is below this fraction of the largest extent of
/// the same kind (position, point, velocity, angular velocity, modes) is held constant by the
/// model, its bound +∞: 1e-6 lies far above the noise of a held quantity in a reference (its
/// tolerance, 1e-14…1e-8 relative to the motion's scale in the studies) and far below the
/// extent of any quantity that moves with the scene (a point near an axis of rotation at a
/// millionth of the largest arm).
inline constexpr double kHeldFraction = 1e-6;

struct ComparisonReport {
  std::vector<QuantityError> quantities;
  double max_rotation_linf = 0.0;  ///< max over bodies, rad
  double max_point_linf = 0.0;     ///< max over tracked points, m
  double max_modal_linf = 0.0;     ///< max over flexible bodies of max_i |q_i − q_i,ref|
  int rotation_count = 0;          ///< bodies measured in rotation
  int point_count = 0;             ///< tracked points measured
  int modal_count = 0;             ///< flexible bodies measured in their modal coordinates
  std::size_t rows = 0;            ///< output times compared
  /// Set by the trajectory contract (trajectory/trajectory_contract.hpp) for files of other codes:
  /// run columns that no quantity measures (unknown to flexref, or not an error quantity such
  /// as `energy`), and the largest |t_run − t_ref| accepted when matching rows.
  std::vector<std::string> ignored_columns;
  double max_time_offset = 0.0;
  /// Named contacts' final wear work and largest worn depth (C.wear_depth, contacts with a wear
  /// law): max over them of |W − W_ref|/|W_ref| at the last output (|W| when W_ref = 0); −1 when
  /// the tables have no `C.wear_work` column.
  double max_wear_relative = -1.0;
};

/// The default metric of every study, of `compare` and of a reference's error estimate
/// (docs/decisions.md, "The default metric"): each body's L∞ geodesic rotation angle and each
/// tracked point's L∞ position error, divided by the largest value that quantity can take
/// (QuantityError::bound: π rad for a rotation, the reference's extent for a point), the
/// largest of these fractions. Dimensionless: an error of 1e-4 is 1e-4 of the quantity's range
/// whatever its unit, and a value of kSaturationFraction or more is a saturated level. Radians
/// and metres are never added.
inline constexpr const char* kDefaultMetric = "relative";

/// Compares two tables with the same columns on the same times (to 1e-9 relative); throws
/// std::invalid_argument naming the first mismatch. Non-finite differences make the norms
/// infinite (a diverged run is never silently small).
ComparisonReport compare_trajectories(const TrajectoryTable& run, const TrajectoryTable& reference);

/// The metrics a study may name: "relative" (the default, kDefaultMetric), "rotation+points"
/// (L∞ rotation angle in rad plus L∞ tracked-point error in m: mixed units, kept to read results
/// made with it, e.g. docs/engines.md), "rotation", "points", "modes"
/// (L∞ over time of max_i |q_i − q_i,ref| over the flexible bodies' modal coordinates),
/// "position", "velocity", "angular_velocity", "wear" (max_wear_relative: the final wear work of
/// the named contacts, docs/output.md "Wear outputs"), "reaction_force" and "reaction_torque"
/// (L∞ over time and the ideal joints of |f − f_ref|, |t − t_ref| of the reactions J.fx…J.tz),
/// "violation" (L∞ over time and the joints of the run's own |J.phi|). Throws std::invalid_argument
/// for any other name, and when the report has no quantity the metric measures (e.g. "rotation"
/// without Euler-parameter columns, "modes" on a rigid scene, "wear" without a named contact): an
/// absent quantity is not an error of 0, and for "relative" when a tracked point has no extent
/// in the reference (it does not move: its error has no range to be a fraction of).
double metric_value(const ComparisonReport& report, const std::string& metric);
/// The names metric_value accepts, the default first.
std::vector<std::string> metric_names();

/// The names of the quantities metric_value(report, metric) takes its value from, e.g.
/// {"book.rotation", "book.corner"}; throws like metric_value.
std::vector<std::string> metric_quantities(const ComparisonReport& report,
                                           const std::string& metric);

/// The unit of a metric's value, stated wherever one is printed: "1" for the default metric (a
/// fraction of range) and for wear (relative), "rad + m" for rotation+points, its quantities'
/// unit for the others ("rad", "m", "m/s", "rad/s", "-" for modal coordinates, "N", "N*m",
/// "m|rad" for a violation). Throws std::invalid_argument for an unknown name.
std::string metric_unit(const std::string& metric);
/// What metric_value(report, metric) is taken from, printed beside it: for the default metric
/// the ranges it divides by, "largest of book.rotation / pi rad, book.corner / 2 m"; for the
/// others the quantities, "book.rotation, book.corner"; throws like metric_value.
std::string metric_terms(const ComparisonReport& report, const std::string& metric);
/// "relative [1]: largest of book.rotation / pi rad, book.corner / 2 m": the metric, its unit
/// and its terms in a comparison against `reference` (the ranges are the reference's own), as a
/// study states them for every error it measures against that reference; "relative [1]" alone
/// when the reference has nothing the metric measures.
std::string describe_metric(const TrajectoryTable& reference, const std::string& metric);

/// The largest L∞ / bound over the quantities metric_value(report, metric) takes its value
/// from (0 when every bound is +∞); throws like metric_value.
double metric_saturation(const ComparisonReport& report, const std::string& metric);
/// "book.rotation: pi rad, book.corner: 2 m": the bounds of the metric's quantities that have
/// one; throws like metric_value.
std::string metric_bounds_text(const ComparisonReport& report, const std::string& metric);

}  // namespace flexref::trajectory
