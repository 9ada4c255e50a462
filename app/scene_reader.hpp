#pragma once
/// \file scene_reader.hpp
/// Reads a scene file (TOML; every key is documented in scenes/README.md) into a Scene.
///
/// Every problem is reported as a core::InputError that names the file, the line and the
/// key (`body[2].mass`: the second [[body]] table, counting from 1) and says what is
/// expected; nothing else ever escapes, whatever the file contains (the reader is fuzzed,
/// tests/app/scene_fuzz_test.cpp).
#include <string>

#include "app/scene.hpp"

namespace flexref::app {

/// Reads and validates the scene file at `path`. Throws core::InputError.
Scene read_scene(const std::string& path);

/// Same, from text in memory; `file_name` is only used in messages and Scene::file.
Scene parse_scene(const std::string& text, const std::string& file_name);

}  // namespace flexref::app
