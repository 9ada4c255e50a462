#pragma once
/// \file element_text.hpp
/// The pieces of the force elements' and joints' one-line descriptions (`flexref check`), for
/// any scalar type: vectors, time profiles, and the bodies and nodes named as the scene names
/// them.
#include <Eigen/Core>
#include <span>
#include <sstream>
#include <string>

#include "core/body.hpp"
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

/// A body as a message names it: "body 'rod'" (its name in the scene), "ground" for a negative
/// index (the ground end of a joint or spring), or "body[2]" — its [[body]] table, counted
/// from 1 as in the scene file — when `bodies` does not reach it (a description without the
/// model's bodies).
std::string body_text(int body, std::span<const Body> bodies);

/// A node of a flexible body as a message names it: "node 'node4'" (its name in the modal data,
/// the name a scene gives in node = "..."), or, for a node without a name (modal data built in
/// code) or without the bodies, "node #5 (unnamed; the 5th node of the modal data)" — the
/// position in the modal data, counted from 1.
std::string node_text(int body, int node, std::span<const Body> bodies);

}  // namespace flexref::core
