#pragma once
/// \file missing_value.hpp
/// The value of a quantity a study could not measure (a failed or unstable level, an order
/// with too few levels, a frequency without a dominant peak): a quiet NaN, which the CSV
/// writer prints as an empty cell (trajectory/trajectory_table.hpp) and the study record omits.
#include <limits>

namespace flexref::studies {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace flexref::studies
