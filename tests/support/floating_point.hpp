#pragma once
/// \file floating_point.hpp
/// The constants that tolerance derivations in the tests start from, defined once for every
/// test program (test files of one folder are compiled together in unity batches, so a constant
/// defined in two of them would collide).
#include <limits>
#include <numbers>

namespace flexref::testing {

/// Machine epsilon of double, 2⁻⁵² ≈ 2.2e-16: the spacing of doubles at 1, twice the unit
/// round-off of one correctly rounded operation.
inline constexpr double kEps = std::numeric_limits<double>::epsilon();

/// π to double precision.
inline constexpr double kPi = std::numbers::pi;

}  // namespace flexref::testing
