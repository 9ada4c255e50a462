#pragma once
/// \file flexible_formulation.hpp
/// Which model a flexible body's equations are (docs/design/model.md); rigid bodies are the same
/// in both.

namespace flexref::core {

enum class FlexibleFormulation {
  kCoupled,  ///< the full floating-frame model (the paper's eq. 19–21)
  kLte,      ///< linear theory of elastodynamics (the paper's §3)
};
/// "coupled" / "lte".
const char* to_string(FlexibleFormulation formulation);

}  // namespace flexref::core
