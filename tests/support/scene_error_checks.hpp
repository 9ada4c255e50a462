#pragma once
/// \file scene_error_checks.hpp
/// require_input_error (input_error_checks.hpp) applied to the scene reader.
#include <string>

#include "scene/scene_reader.hpp"
#include "tests/support/input_error_checks.hpp"

namespace flexref::testing {

/// Requires scene::parse_scene to refuse `text` with a core::InputError at `line` and `key`
/// whose message contains `fragment` (when not empty).
inline void require_scene_error(const std::string& text, int line, const std::string& key,
                                const std::string& fragment = "") {
  require_input_error(
      [](const std::string& t, const std::string& file) { return scene::parse_scene(t, file); },
      "parse_scene", text, line, key, fragment);
}

}  // namespace flexref::testing
