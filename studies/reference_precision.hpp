#pragma once
/// \file reference_precision.hpp
/// The arithmetic of a study's reference as the user asks for it (--reference-precision,
/// Python's precision=; docs/precision.md): double, extended, quad, or auto (the reference
/// policy's choice: studies/reference_policy.hpp).
#include <string_view>

namespace flexref::studies {

/// The reference precision a study asks for.
enum class ReferencePrecision {
  kAuto,      ///< double, and quad when double cannot certify everything (the cost guard)
  kDouble,    ///< the double reference alone
  kExtended,  ///< an 80-bit extended reference
  kQuad,      ///< a binary128 reference
};

/// "auto", "double", "extended" or "quad"; throws std::invalid_argument naming the accepted
/// values.
ReferencePrecision parse_reference_precision(std::string_view name);
const char* to_string(ReferencePrecision precision);

}  // namespace flexref::studies
