#include "core/prescribed_motion.hpp"

#include <cmath>
#include <sstream>

namespace flexref::core {

std::string AngleLaw::describe(std::string_view rate_unit) const {
  std::ostringstream out;
  if (kind == Kind::kConstantRate) {
    out << "constant rate " << rate << " " << rate_unit;
  } else {
    out << "spin-up to " << rate << " " << rate_unit << " over " << spin_up_time << " s";
  }
  return out.str();
}

}  // namespace flexref::core
