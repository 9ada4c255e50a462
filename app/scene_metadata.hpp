#pragma once
/// \file scene_metadata.hpp
/// What a result records about its scene (the [scene] table of its sidecar or study.toml), and
/// the check that two results come from the same scene (docs/decisions.md, "Scene identity").
#include <string>

#include "scene/scene.hpp"
#include "studies/study_record.hpp"
#include "trajectory/reference_sidecar.hpp"

namespace flexref::app {

/// The identity a result of `scene` records in its sidecar (scene_record).
trajectory::SceneIdentity scene_identity(const std::string& scene_file, const scene::Scene& scene);

/// A result record (studies/study_record.hpp) that starts with the [scene] table: the scene
/// file, its name, the hash of its physics (scene/scene_identity.hpp), the creation time and
/// the model formulation (`model = "coupled"` or `"lte"`, the --model option).
studies::StudyRecord scene_record(const std::string& scene_file, const scene::Scene& scene);

/// Refuses (std::invalid_argument, exit 1) results of different scenes (trajectory::scene_mismatch)
/// unless `allow`; with `allow` a mismatch is a warning on standard error. Returns the mismatch
/// ("" when none).
std::string check_same_scene(const trajectory::SceneIdentity& a, const std::string& a_what,
                             const trajectory::SceneIdentity& b, const std::string& b_what,
                             bool allow);

}  // namespace flexref::app
