#pragma once
/// \file wear_command.hpp
/// `flexref wear`: the multi-scale (cycle-jump) scheme of wear on a scene (docs/wear.md,
/// studies/wear_cycle_jump.hpp).
#include <string>

#include "app/default_model.hpp"
#include "core/flexible_formulation.hpp"

namespace flexref::app {

struct WearCommandOptions {
  std::string scene;
  double window = 0.025;          ///< T_w, s
  double transient = 0.05;        ///< T_tr, s
  double first_transient = -1.0;  ///< the first window's, s (< 0: the transient)
  double jump = 0.0;              ///< D, s (0: a tenth of the slow time)
  double until = 0.0;             ///< T, s (0: the scene's end time)
  std::string slow = "heun";
  std::string solver = "cvode";
  double rtol = 1e-8;
  core::FlexibleFormulation model = kDefaultFormulation;
  std::string out_dir = "out/wear";
};

int wear_command(const WearCommandOptions& options);

}  // namespace flexref::app
