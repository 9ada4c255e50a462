#pragma once
/// \file precise_comparison.hpp
/// `compare` beyond double (docs/precision.md, "compare"): trajectory files whose values carry
/// more digits than a double (extended and quad references, 21 and 36 significant digits) are
/// compared with trajectory/error_metrics.hpp's norms computed in the higher of the two files'
/// precisions, each value parsed from its text in its own file's precision, so that nothing is
/// rounded to double before the subtraction.
#include <string>
#include <vector>

#include "precision/precision.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {

/// A trajectory CSV with the text of its values and the precision its sidecar records.
struct PreciseTable {
  std::string path;
  Precision precision = Precision::kDouble;
  std::vector<std::string> columns;
  std::vector<double> times;
  std::vector<std::vector<std::string>> text;  ///< per row, every column after `t`
};

/// Reads `path` (a flexref trajectory CSV the trajectory contract already accepted) with its
/// precision from `path`.meta.toml ([integrator] precision; double when absent). Throws
/// core::InputError naming the file and line for a row whose cell count differs from the
/// header's.
PreciseTable read_precise_table(const std::string& path);

/// Whether the two files can be compared precisely: one of them is extended or quad, and they
/// have the same columns and the same output times.
bool precisely_comparable(const PreciseTable& run, const PreciseTable& reference);

/// trajectory::compare_trajectories of the two files in the higher of their precisions (a double
/// file's values are its doubles, exactly representable there). Requires the same columns and
/// times; throws std::invalid_argument otherwise.
trajectory::ComparisonReport compare_precisely(const PreciseTable& run,
                                               const PreciseTable& reference);

}  // namespace flexref::precision
