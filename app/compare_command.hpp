#pragma once
/// \file compare_command.hpp
/// `flexref compare RUN REFERENCE`: error norms of a run against a reference under the
/// trajectory contract (docs/external.md), per body and point, and the run's joints.
#include <string>

#include "trajectory/error_metrics.hpp"

namespace flexref::app {

struct CompareOptions {
  std::string run;
  std::string reference;
  std::string metric = trajectory::kDefaultMetric;
  bool json = false;              ///< machine-readable output
  double time_tolerance = 1e-6;   ///< trajectory::ContractOptions
  double euler_tolerance = 1e-6;  ///< trajectory::ContractOptions
  /// Compare files whose sidecars name different scenes (refused otherwise, exit 1).
  bool allow_scene_mismatch = false;
  /// The scene whose ideal joints are measured in the run (trajectory/joint_violation.hpp);
  /// "": the reference's sidecar's [scene] file, when it still holds the reference's physics.
  std::string scene;
};
int compare_command(const CompareOptions& options);

}  // namespace flexref::app
