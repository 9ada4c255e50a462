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

/// `text` with the first occurrence of `from` replaced by `to`; `from` must occur (a scene edit
/// that finds nothing to edit would test the unedited scene).
inline std::string replace_first(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace flexref::testing
