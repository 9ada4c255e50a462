#pragma once
/// \file wear_jump_command.hpp
/// `flexref wear-jump`: the multi-scale scheme of wear against the fully coupled reference over
/// a ladder of jumps and windows (docs/wear.md, studies/wear_jump.hpp).
#include <string>
#include <vector>

#include "app/default_model.hpp"
#include "core/flexible_formulation.hpp"

namespace flexref::app {

struct WearJumpCommandOptions {
  std::string scene;
  std::vector<std::string> slow = {"euler", "heun", "ab2"};
  std::vector<int> jumps = {2, 4, 8, 16, 32};  ///< jump counts over the slow time
  std::vector<double> windows = {
      0.025};  ///< T_w values, s (two periods of the bundled 80 Hz forcing)
  /// T_tr, s: 4 periods of the bundled 80 Hz forcing (docs/wear.md measures 0.05 against 0.1 s
  /// on tube_support_wear).
  double transient = 0.05;
  double first_transient = -1.0;  ///< s (< 0: the transient)
  double until = 0.0;             ///< T, s (0: the scene's end time)
  std::string solver = "cvode";
  double rtol = 1e-8;
  double estimate_factor = 10.0;
  int jobs = 1;
  core::FlexibleFormulation model = kDefaultFormulation;
  std::string out_dir = "out/wear_jump";
};

int wear_jump_command(const WearJumpCommandOptions& options);

}  // namespace flexref::app
