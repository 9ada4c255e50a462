#include "studies/stability_parameter.hpp"

#include <stdexcept>
#include <string>

namespace flexref::studies {

StabilityParameter parse_stability_parameter(std::string_view name) {
  if (name == "spin") return StabilityParameter::kSpin;
  if (name == "inertia_ratio") return StabilityParameter::kInertiaRatio;
  if (name == "modal_frequency") return StabilityParameter::kModalFrequency;
  if (name == "contact_stiffness") return StabilityParameter::kContactStiffness;
  throw std::invalid_argument("stability: unknown parameter '" + std::string(name) +
                              "': expected spin, inertia_ratio, modal_frequency or "
                              "contact_stiffness");
}

const char* to_string(StabilityParameter parameter) {
  switch (parameter) {
    case StabilityParameter::kSpin:
      return "spin";
    case StabilityParameter::kInertiaRatio:
      return "inertia_ratio";
    case StabilityParameter::kModalFrequency:
      return "modal_frequency";
    case StabilityParameter::kContactStiffness:
      return "contact_stiffness";
  }
  return "spin";
}

bool is_linear_sweep(StabilityParameter parameter) {
  return parameter == StabilityParameter::kModalFrequency ||
         parameter == StabilityParameter::kContactStiffness;
}

}  // namespace flexref::studies
