#pragma once
/// \file lte_map_command.hpp
/// `flexref lte-map`: the LTE model's error against the coupled model over a grid of spin
/// ratio Ω0/ω1 and flexible/rigid inertia ratio, on a scene with a free flexible body
/// (studies/lte_map.hpp, docs/lte_map.md).
#include <string>
#include <string_view>
#include <vector>

#include "app/work_limits.hpp"
#include "studies/reference_solver_name.hpp"

namespace flexref::app {

/// The model the LTE model is measured against (--truth).
enum class LteMapTruth {
  kAuto,       ///< stiffened when the body can be, else coupled
  kStiffened,  ///< the coupled model with geometric stiffening
  kCoupled,    ///< the classical coupled model
};
/// "auto", "stiffened" or "coupled"; throws std::invalid_argument naming the accepted values.
LteMapTruth parse_lte_map_truth(std::string_view name);
const char* to_string(LteMapTruth truth);

struct LteMapCommandOptions {
  std::string scene;
  /// Spin ratios x = Ω0/ω1; when empty, spin_count values spaced logarithmically in
  /// [spin_min, spin_max].
  std::vector<double> spin_ratios;
  double spin_min = 0.01;
  double spin_max = 0.5;
  int spin_count = 11;
  /// Inertia ratios y = I_flex/I_rigid; when empty, inertia_count log-spaced values in
  /// [inertia_min, inertia_max].
  std::vector<double> inertia_ratios;
  double inertia_min = 1e-4;
  double inertia_max = 1.0;
  int inertia_count = 11;
  studies::ReferenceSolver solver = studies::ReferenceSolver::kCvode;
  double rtol = 1e-10;
  double estimate_factor = 10.0;  ///< the accuracy check reruns at estimate_factor·rtol
  bool scale_loads = true;
  LteMapTruth truth = LteMapTruth::kAuto;
  std::string point;      ///< tracked node point (empty: the node farthest from Br)
  double end_time = 0.0;  ///< s (0: the scene's)
  int jobs = 0;           ///< 0: all cores
  std::string out_dir = "out/lte_map";
  WorkLimits limits;  ///< --max-rows
};

int lte_map_command(const LteMapCommandOptions& options);

}  // namespace flexref::app
