#pragma once
/// \file precision.hpp
/// The arithmetic of a reference solution (docs/precision.md): IEEE double, x87 80-bit
/// extended (`long double` on x86-64 Linux, 64-bit mantissa) or IEEE binary128 (quad,
/// boost::multiprecision::float128 on libquadmath, 113-bit mantissa).
#include <string>

namespace flexref::precision {

enum class Precision { kDouble, kExtended, kQuad };

/// "double", "extended" or "quad"; throws std::invalid_argument naming the accepted values.
Precision parse_precision(const std::string& name);
const char* to_string(Precision precision);
/// Significant decimal digits that round-trip a value of that precision: 17, 21, 36
/// (⌈1 + p log10 2⌉ for the mantissa bits p = 53, 64, 113).
int significant_digits(Precision precision);
/// The unit round-off ε/2 of the precision: 1.1e-16, 5.4e-20, 9.6e-35.
double unit_roundoff(Precision precision);

}  // namespace flexref::precision
