#pragma once
/// \file refusal.hpp
/// The message of precision/'s models when a scene has a part they do not carry: the scene
/// file, line and table of the part, what it is, and what the model does carry. Internal to
/// precision/.
#include <stdexcept>
#include <string>

#include "scene/scene_spec.hpp"

namespace flexref::precision {

/// Throws std::invalid_argument: "FILE:LINE: TABLE: WHAT is not in the extended/quad model
/// SCOPE; use --precision double" (the scene's name instead of the place for parts built in
/// code).
[[noreturn]] inline void refuse_part(const scene::SceneSpec& spec, const scene::SpecSource& source,
                                     const std::string& what, const std::string& scope) {
  const std::string where =
      source.file.empty() ? spec.name
                          : source.file + ":" + std::to_string(source.line) + ": " + source.path;
  throw std::invalid_argument(where + ": " + what + " is not in the extended/quad model " + scope +
                              "; use --precision double");
}

}  // namespace flexref::precision
