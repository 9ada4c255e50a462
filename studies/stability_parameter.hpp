#pragma once
/// \file stability_parameter.hpp
/// The parameter a stability study sweeps (docs/design/studies.md, "Stability"): the spin rate
/// or inertia ratio of a free rigid body (studies/stability.hpp), the top modal frequency of a
/// beam or the stiffness of a penalty contact (studies/stability_sweeps.hpp).
#include <string_view>

namespace flexref::studies {

enum class StabilityParameter {
  kSpin,              ///< |W0|, rad/s
  kInertiaRatio,      ///< J3/J1
  kModalFrequency,    ///< ω_max, rad/s
  kContactStiffness,  ///< k, N/m
};

/// "spin", "inertia_ratio", "modal_frequency" or "contact_stiffness"; throws
/// std::invalid_argument naming the accepted values.
StabilityParameter parse_stability_parameter(std::string_view name);
const char* to_string(StabilityParameter parameter);
/// Whether the parameter is swept on a linear oscillator (modal frequency, contact stiffness)
/// rather than a free rigid body (spin, inertia ratio).
bool is_linear_sweep(StabilityParameter parameter);

}  // namespace flexref::studies
