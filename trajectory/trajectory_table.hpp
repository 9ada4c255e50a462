#pragma once
/// \file trajectory_table.hpp
/// A trajectory as named columns, the common currency of every integrator's output: the CSV
/// files `run`, `reference` and studies write, and what `compare` and the error metrics read.
///
/// Columns (docs/output.md): `t`; per body B: `B.x,B.y,B.z` (frame origin Bo, world, m),
/// `B.e0..B.e3` (Euler parameters B → W), `B.vx,B.vy,B.vz` (velocity of Bo, world, m/s),
/// `B.W1..B.W3` (body-frame angular velocity, rad/s); per tracked point P of B: `B.P.x,B.P.y,
/// B.P.z` (world, m; node points of flexible bodies deformed); for a flexible body with n modes
/// `B.q1..B.qn` (modal coordinates) and `B.qd1..B.qdn` (their rates, 1/s); for a prescribed
/// body `B.drive_torque` (N·m, about the axis); then `energy` (J): kinetic + potential of
/// conservative elements (contact and joint springs included) + elastic energy ½ q_fᵀ K q_f;
/// when the model dissipates (Model::dissipates()), `dissipated_work` (W_d(t), J, from
/// Trajectory::dissipated_work; NaN when the integrator did not track it), `applied_work` (W_a of
/// harmonic loads, Trajectory::extra_work, when tracked) and `energy_balance`
/// (E(t) − E(0) + W_d(t) − W_a(t), J); last, per named contact C, `C.fn`, `C.slip_speed` (from
/// the state), `C.wear_work` (Trajectory::extra_work) and `C.impacts` (Trajectory::impacts).
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::trajectory {

struct TrajectoryTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;

  /// Index of a column, or −1.
  int column(const std::string& name) const;
  std::size_t size() const { return rows.size(); }
  double time(std::size_t row) const { return rows[row][0]; }
};

/// The column names for a model, in file order (ColumnLayout::of, trajectory/column_layout.hpp).
std::vector<std::string> trajectory_columns(const core::Model& model);
/// The unit of each column of trajectory_columns(model), in the same order (docs/output.md):
/// "s", "m", "-" (Euler parameters), "m/s", "rad/s", "N*m", "J"; modal coordinates carry the
/// unit their mode normalization gives them, written "modal" and "modal/s".
std::vector<std::string> trajectory_units(const core::Model& model);
/// Tabulates states at their times (energy evaluated with the load branch active at t).
TrajectoryTable tabulate(const core::Model& model, const core::Trajectory& trajectory);

/// Writes the table as CSV (17 significant digits) under the output rule (io/output_file.hpp):
/// a file atomically (a temporary beside it, then renamed, so an interrupted run never leaves a
/// half-written file), a link's target, a FIFO or device directly, `-` to standard output.
void write_csv(const TrajectoryTable& table, const std::string& path);
/// A free-text CSV field (a status, a classification) that every CSV reader splits alike,
/// numpy.genfromtxt included: commas become semicolons, double quotes apostrophes, line breaks
/// spaces; never quoted.
std::string csv_text(std::string text);
/// A number for a CSV cell: the shortest text that reads back as the same double, and an empty
/// cell for NaN (a value that was not measured; no file gets a NaN).
std::string csv_number(double x);
/// Reads a CSV written by write_csv; throws core::InputError naming file and line.
TrajectoryTable read_csv(const std::string& path);

}  // namespace flexref::trajectory
