#include "studies/reference_precision.hpp"

#include <stdexcept>
#include <string>

namespace flexref::studies {

ReferencePrecision parse_reference_precision(std::string_view name) {
  if (name == "auto") return ReferencePrecision::kAuto;
  if (name == "double") return ReferencePrecision::kDouble;
  if (name == "extended") return ReferencePrecision::kExtended;
  if (name == "quad") return ReferencePrecision::kQuad;
  throw std::invalid_argument("reference precision '" + std::string(name) +
                              "': expected auto, double, extended or quad");
}

const char* to_string(ReferencePrecision precision) {
  switch (precision) {
    case ReferencePrecision::kAuto:
      return "auto";
    case ReferencePrecision::kDouble:
      return "double";
    case ReferencePrecision::kExtended:
      return "extended";
    case ReferencePrecision::kQuad:
      return "quad";
  }
  return "double";
}

}  // namespace flexref::studies
