#pragma once
/// \file element_text.hpp
/// The pieces of the force elements' one-line descriptions (`flexref check`), for any scalar
/// type.
#include <Eigen/Core>
#include <sstream>
#include <string>

#include "core/time_profile.hpp"

namespace flexref::core {

/// "(x, y, z)" at the stream's default precision.
template <typename S>
std::string vector_text(const Eigen::Matrix<S, 3, 1>& v) {
  std::ostringstream out;
  out << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return out.str();
}

/// "constant", "sin2 pulse on [a, b)", "rectangular pulse on [a, b)" or "harmonic sin(...)".
std::string profile_text(const TimeProfile& profile);

}  // namespace flexref::core
