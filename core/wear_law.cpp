#include "core/wear_law.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace flexref::core {
namespace {

void require_wear_value(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream out;
    out << "wear law: " << what << " must be positive and finite, got " << value;
    throw std::invalid_argument(out.str());
  }
}

}  // namespace

double WearLaw::sector_area() const {
  return 2.0 * std::numbers::pi * radius / static_cast<double>(sectors) * thickness;
}

std::string WearLaw::describe() const {
  std::ostringstream out;
  out << "wear law " << name() << ", coefficient " << coefficient
      << (kind == Kind::kArchard ? "" : " 1/Pa");
  if (kind == Kind::kArchard) out << ", hardness " << hardness << " Pa";
  if (sectors > 0) {
    out << ", " << sectors << " sectors of " << sector_area() << " m^2 (radius " << radius
        << " m, thickness " << thickness << " m)";
  } else {
    out << ", pin area " << area << " m^2";
  }
  out << ", acceleration " << acceleration;
  return out.str();
}

void validate_wear_law(const WearLaw& law, bool gap_support, int depth_count) {
  require_wear_value(law.coefficient, "the coefficient");
  require_wear_value(law.acceleration, "the acceleration factor");
  if (law.kind == WearLaw::Kind::kArchard) require_wear_value(law.hardness, "the hardness");
  if (gap_support) {
    if (law.sectors < 1) {
      throw std::invalid_argument("wear law: a gap support needs sectors >= 1, got " +
                                  std::to_string(law.sectors));
    }
    require_wear_value(law.thickness, "the support's thickness");
    require_wear_value(law.radius, "the hole's radius");
  } else {
    require_wear_value(law.area, "the pin area");
  }
  if (!law.initial_depth.empty() && static_cast<int>(law.initial_depth.size()) != depth_count) {
    throw std::invalid_argument("wear law: " + std::to_string(law.initial_depth.size()) +
                                " initial depths for " + std::to_string(depth_count) +
                                " points or sectors");
  }
  for (double h : law.initial_depth) {
    if (!(h >= 0.0) || !std::isfinite(h)) {
      throw std::invalid_argument("wear law: an initial depth must be finite and >= 0");
    }
  }
}

}  // namespace flexref::core
