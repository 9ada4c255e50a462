#pragma once
/// \file converge_command.hpp
/// `flexref converge SCENE`: observed orders of convergence of the schemes and of external
/// methods against a certified reference (docs/design/studies.md, "Convergence").
#include <string>
#include <vector>

#include "app/default_model.hpp"
#include "app/work_limits.hpp"
#include "core/flexible_formulation.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "studies/reference_precision.hpp"
#include "studies/reference_solver_name.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::app {

struct ConvergeOptions {
  std::string scene;
  core::FlexibleFormulation model = kDefaultFormulation;
  std::vector<std::string> schemes = lie::default_scheme_names();
  lie::MethodOptions method_options;  ///< --rho-inf, --perturbed-start
  double dt = 1e-2;
  int levels = 6;
  std::string metric = trajectory::kDefaultMetric;
  studies::ReferenceSolver reference_solver = studies::ReferenceSolver::kAuto;
  double reference_rtol = 1e-12;
  int jobs = 0;  ///< 0: all cores
  std::string out_dir = "out/converge";
  WorkLimits limits;
  bool schemes_given = false;  ///< --schemes was given (else none run beside --external/--runs)
  bool dt_given = false;  ///< --dt was given (else the coarsest step is dt or the output interval)
  std::string external;   ///< --external command template (docs/external.md)
  std::vector<std::string> runs;  ///< --runs DT=FILE ...
  std::string label;              ///< --label of the external method
  int claimed_order = 0;          ///< --order: the external method's claimed order
  double timeout = 3600.0;        ///< --timeout per external run [s], 0: none
  /// auto | double | extended | quad (docs/precision.md): auto repeats the study with a quad
  /// reference when the double one cannot certify every level and the scene allows it.
  studies::ReferencePrecision reference_precision = studies::ReferencePrecision::kAuto;
  /// auto's wall-time bound on the quad reference, s (0: none; docs/precision.md, "Cost guard").
  double reference_budget = kDefaultReferenceBudget;
  /// --runs/--external files whose sidecars name another scene are used anyway.
  bool allow_scene_mismatch = false;
};
int converge_command(const ConvergeOptions& options);

}  // namespace flexref::app
