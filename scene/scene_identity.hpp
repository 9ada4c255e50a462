#pragma once
/// \file scene_identity.hpp
/// What identifies a scene's physics, so that results can say which scene they are of and a
/// comparison can refuse files of two different scenes (docs/decisions.md, "Scene identity").
///
/// The hash is of the parsed scene, not of its bytes: comments, blank lines, key order, the
/// spelling of numbers (`2`, `2.0`, `2e0`) and of strings do not change it; every value does.
/// Four [scene] keys are left out because they choose what to output, not the physics: `name`
/// (recorded beside the hash), `description`, `end_time` and `output_step` — a run over
/// [0, 2] is comparable with a reference of the same scene over [0, 100]. A flexible body's
/// modal-data file is part of the physics: its parsed content is hashed too, so editing that
/// file changes the hash while moving it (and its path in the scene) does not change it.
#include <string>
#include <toml.hpp>
#include <vector>

namespace flexref::scene {

/// "fnv1a64:" and 16 hexadecimal digits: FNV-1a (64 bits) of the canonical text of the scene
/// document (without the four keys above) followed by that of each modal-data document, in the
/// order given. FNV-1a detects edits, it is no cryptographic signature.
std::string scene_hash(const toml::value& scene_document,
                       const std::vector<toml::value>& modal_documents);

/// The canonical text the hash is taken of (tests): tables with their keys sorted, numbers as
/// exact hexadecimal doubles, strings length-prefixed.
std::string canonical_text(const toml::value& value);

}  // namespace flexref::scene
