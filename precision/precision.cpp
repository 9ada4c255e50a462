#include "precision/precision.hpp"

#include <cmath>
#include <stdexcept>

namespace flexref::precision {

Precision parse_precision(const std::string& name) {
  if (name == "double") return Precision::kDouble;
  if (name == "extended") return Precision::kExtended;
  if (name == "quad") return Precision::kQuad;
  throw std::invalid_argument("precision '" + name + "': use double, extended or quad");
}

const char* to_string(Precision precision) {
  switch (precision) {
    case Precision::kDouble:
      return "double";
    case Precision::kExtended:
      return "extended";
    case Precision::kQuad:
      return "quad";
  }
  return "double";
}

int significant_digits(Precision precision) {
  switch (precision) {
    case Precision::kDouble:
      return 17;
    case Precision::kExtended:
      return 21;
    case Precision::kQuad:
      return 36;
  }
  return 17;
}

double unit_roundoff(Precision precision) {
  switch (precision) {
    case Precision::kDouble:
      return std::ldexp(1.0, -53);
    case Precision::kExtended:
      return std::ldexp(1.0, -64);
    case Precision::kQuad:
      return std::ldexp(1.0, -113);
  }
  return std::ldexp(1.0, -53);
}

}  // namespace flexref::precision
