#pragma once
/// \file trajectory_contract.hpp
/// The trajectory contract (docs/external.md): how flexref reads the trajectories of other
/// codes and measures them against a reference.
///
/// A run is a table with a `t` column and any subset of the standard columns of
/// docs/output.md (`B.x B.y B.z`, `B.e0..B.e3`, `B.vx..`, `B.W1..B.W3`, `B.P.x..`, `B.q1..`),
/// in any order. Columns flexref does not know are ignored and listed in the report; columns
/// that name a body, point or mode the reference does not have are errors. Each standard
/// group (a position, an attitude, a velocity, an angular velocity, a point) is compared only
/// as a whole. Rows may be any subset of the reference's output times, each matched to the
/// nearest output time within `time_tolerance` × the reference's output step.
///
/// Nothing can fool the comparison: a non-finite or unparsable value in a measured column,
/// Euler parameters whose norm is off 1 by more than `euler_norm_tolerance`, a missing `t`, a
/// time off the reference's grid, two rows at one output time, or a metric with nothing to
/// measure are core::InputError naming the source, the line (row) and the column.
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {

struct ContractOptions {
  /// A run row at time t matches the reference's output time t_k when |t − t_k| ≤ this ×
  /// the reference's output step (its smallest time spacing). 1e-6 accepts times printed with
  /// 7 significant digits or accumulated as t += h over 10⁶ steps (drift ~1e-10 t), and a
  /// time offset δ changes a state by at most |ẏ|·δ, far below any error worth measuring.
  double time_tolerance = 1e-6;
  /// |‖θ‖ − 1| allowed in Euler parameters. 1e-6 accepts 7-significant-digit output and
  /// single-precision normalization; a run that does not keep its quaternions unit (a drift
  /// of O(h), or the all-zero parameters of a missing attitude) is refused instead of being
  /// silently normalized by the geodesic angle.
  double euler_norm_tolerance = 1e-6;
  /// The run's fixed step h when known (converge --external and --runs; 0: unknown). A program
  /// whose clock is accumulated as t += h carries up to n rounding errors of at most ε·t/2 each
  /// after n = t/h steps: with h known, a row also matches t_k when |t − t_k| ≤ ε t_k² / h
  /// (twice that bound), which a long run at a small step can exceed 1e-6 output steps by (a
  /// 100 s run written every 0.01 s at h = 1e-5: drift 2e-8 > 1e-8). The time is a label: the
  /// state after n steps is the state at n·h whatever the clock says, so accepting the drift
  /// adds no error.
  double run_step = 0.0;
};

/// A trajectory as another code wrote it.
struct RunData {
  std::string source;      ///< file path, or a name for data given in memory
  int header_line = 1;     ///< line of the header in the source
  TrajectoryTable table;   ///< columns as named in the source; unparsable cells are NaN
  std::vector<int> lines;  ///< source line of each row (the row number for in-memory data)
  /// Cells that are not numbers: (row, column, text). Only an error in measured columns.
  struct BadCell {
    std::size_t row, column;
    std::string text;
  };
  std::vector<BadCell> bad_cells;
  /// The CPU time of the integration alone as the program reported it, in a comment line
  /// `# cpu_seconds = X` (docs/external.md); NaN when the file has none.
  double reported_cpu_seconds = std::numeric_limits<double>::quiet_NaN();
  int reported_cpu_line = 0;  ///< its line
};

/// The UTF-8 byte-order mark some programs (spreadsheets, Windows editors) write at the start of
/// a CSV; the readers skip it.
inline constexpr std::string_view kUtf8ByteOrderMark = "\xEF\xBB\xBF";

/// Reads a CSV under the contract: `#` comment lines and blank lines anywhere, spaces and tabs
/// around names and values, CRLF line ends, a UTF-8 byte-order mark; a comment
/// `# cpu_seconds = X` is the program's report of its integration's CPU time. Throws
/// core::InputError for a directory, an unreadable or empty file, duplicate or empty column
/// names, a row with the wrong number of cells, or a cpu_seconds that is not a finite number
/// ≥ 0 or is given twice.
RunData read_run_csv(const std::string& path);

/// Wraps columns given in memory (the Python module's arrays); `source` names them in errors
/// and rows count from 1. Throws core::InputError when the columns differ in length.
RunData run_from_columns(const std::string& source, std::vector<std::string> names,
                         const std::vector<std::vector<double>>& columns);

/// Checks a reference under the same rules (a `t` column, finite values and unit Euler
/// parameters in its standard columns, increasing times) and returns its table.
TrajectoryTable checked_reference(const RunData& reference, const ContractOptions& options = {});

/// Compares a run with a reference table under the contract. The report's quantities are those
/// the run's columns allow; ignored_columns and max_time_offset are filled in.
ComparisonReport compare_run(const RunData& run, const TrajectoryTable& reference,
                             const ContractOptions& options = {});

}  // namespace flexref::trajectory
