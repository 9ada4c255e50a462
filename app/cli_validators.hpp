#pragma once
/// \file cli_validators.hpp
/// CLI11 validators with plain messages: "'abc' is not a number", "must be positive, got 0"
/// (the value quoted as the user wrote it), ranges printed with a few digits (CLI11's
/// PositiveNumber prints its range with 300 digits and calls a word "not in range"). Each
/// refuses NaN and infinities.
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
/// A whole number >= 1 of any size a double holds (a count: --max-steps, --max-rows).
CLI::Validator positive_integer();

/// A number in messages: the shortest text that reads back as the same double ("1e-16",
/// "0.001", "1e+15"), never std::to_string's fixed six decimals ("0.000000").
std::string number_text(double x);

}  // namespace flexref::app
