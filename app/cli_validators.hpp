#pragma once
/// \file cli_validators.hpp
/// CLI11 validators with plain messages (issue 17): "'abc' is not a number", "must be
/// positive, got 0", ranges printed with a few digits (CLI11's PositiveNumber prints its range
/// with 300 digits and calls a word "not in range"). Each refuses NaN and infinities.
#include <CLI/CLI.hpp>
#include <string>

namespace flexref::app {

/// A finite number > 0.
CLI::Validator positive_number();
/// A finite number >= 0.
CLI::Validator non_negative_number();
/// A finite number in [lo, hi].
CLI::Validator number_in(double lo, double hi);
/// An integer in [lo, hi] (no fraction, no exponent beyond what is an exact integer).
CLI::Validator integer_in(long lo, long hi);

}  // namespace flexref::app
