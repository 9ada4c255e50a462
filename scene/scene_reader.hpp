#pragma once
/// \file scene_reader.hpp
/// Reads a scene file (TOML; every key is documented in scenes/README.md) into a Scene.
///
/// Every problem is reported as a core::InputError that names the file, the line and the
/// key (`body[2].mass`: the second [[body]] table, counting from 1) and says what is
/// expected; nothing else ever escapes, whatever the file contains (the reader is fuzzed,
/// tests/scene/scene_fuzz_test.cpp).
#include <string>

#include "scene/scene.hpp"

namespace flexref::scene {

/// Reads and validates the scene file at `path`. Throws core::InputError. The formulation of
/// flexible bodies' equations is a command-line choice, not part of the scene
/// (`--model coupled|lte`); rigid bodies are the same in both.
Scene read_scene(const std::string& path,
                 core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled);

/// Same, from text in memory; `file_name` is used in messages and Scene::file, and relative
/// modal-data paths are resolved from its directory.
Scene parse_scene(const std::string& text, const std::string& file_name,
                  core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled);

}  // namespace flexref::scene
