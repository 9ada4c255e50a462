#pragma once
/// \file run_command.hpp
/// `flexref run SCENE --scheme S --dt H -o FILE`: one run of a registered scheme at a fixed
/// step, checked against the scene's invariants and joints, written as a trajectory CSV with
/// its sidecar.
#include <string>

#include "app/default_model.hpp"
#include "app/work_limits.hpp"
#include "core/flexible_formulation.hpp"
#include "lie/method_options.hpp"

namespace flexref::app {

struct RunOptions {
  std::string scene;
  core::FlexibleFormulation model = kDefaultFormulation;
  std::string scheme = "c2";
  lie::MethodOptions method_options;  ///< --rho-inf, --perturbed-start
  double dt = 1e-3;
  std::string output;
  WorkLimits limits;
};
int run_command(const RunOptions& options);

}  // namespace flexref::app
