#pragma once
/// \file external_methods.hpp
/// The external methods of `converge` and `work-precision` (docs/external.md): another code's
/// integrator run once per level from a command template, or runs already made.
#include <string>
#include <vector>

#include "studies/convergence.hpp"
#include "studies/study_output.hpp"
#include "trajectory/reference_sidecar.hpp"

namespace flexref::app {

/// `external`, a command template run once per level, writing its files as
/// `run_<label>_<level>.csv` into the study's staging folder `out`; or `runs`, "DT=FILE" pairs of
/// runs already made.
struct ExternalOptions {
  std::string scene;
  std::string external;
  std::vector<std::string> runs;
  std::string label;
  int claimed_order = 0;
  double timeout = 3600.0;
  /// The studied scene: a file whose sidecar (FILE.meta.toml) names another scene is refused
  /// (--runs: before any work, exit 1; --external: that level fails) unless
  /// allow_scene_mismatch (app/scene_metadata.hpp, check_same_scene).
  trajectory::SceneIdentity scene_identity;
  bool allow_scene_mismatch = false;
};
/// The studies::ExternalMethod of `options`; throws std::invalid_argument for a malformed pair
/// or label.
std::vector<studies::ExternalMethod> external_methods(const ExternalOptions& options,
                                                      const studies::StudyOutput& out);

}  // namespace flexref::app
