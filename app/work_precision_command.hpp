#pragma once
/// \file work_precision_command.hpp
/// The `work-precision` subcommand (docs/design/studies.md, "Work-precision"): error against CPU
/// time for each scheme over a range of steps and each reference solver over a range of
/// tolerances, the cheapest method per target error, a CSV, a table, study.toml and a plot.
#include <string>
#include <vector>

#include "app/default_model.hpp"
#include "app/work_limits.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "studies/reference_precision.hpp"
#include "studies/reference_solver_name.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::app {

struct WorkPrecisionOptions {
  std::string scene;
  core::FlexibleFormulation model = kDefaultFormulation;  ///< --model coupled|lte
  std::vector<std::string> schemes = lie::default_scheme_names();
  lie::MethodOptions method_options;  ///< --rho-inf, --perturbed-start
  double dt = 1e-2;                   ///< coarsest step [s]
  bool dt_given = false;  ///< --dt was given (else dt or the output interval, the shorter)
  int levels = 6;         ///< number of steps dt, dt/2, …
  std::vector<std::string> solvers{"ida", "cvode", "arkode", "odeint"};
  std::vector<double> tolerances{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  int repeats = 3;  ///< CPU time: minimum over this many runs
  std::string metric = trajectory::kDefaultMetric;
  studies::ReferenceSolver reference_solver = studies::ReferenceSolver::kAuto;
  double reference_rtol = 1e-12;
  int jobs = 0;  ///< 0: all cores (timings are cleanest with 1)
  std::string out_dir = "out/work_precision";
  WorkLimits limits;
  std::string external;     ///< --external command template (docs/external.md)
  std::string label;        ///< --label of the external method
  double timeout = 3600.0;  ///< --timeout per external run [s], 0: none
  /// auto | double | extended | quad (docs/precision.md), as for converge.
  studies::ReferencePrecision reference_precision = studies::ReferencePrecision::kAuto;
  /// auto's wall-time bound on the quad reference, s (0: none; docs/precision.md, "Cost guard").
  double reference_budget = kDefaultReferenceBudget;
  /// --external files whose sidecars name another scene are used anyway.
  bool allow_scene_mismatch = false;
};

/// Runs the study on the scene and writes work_precision.csv, work_precision.txt, study.toml,
/// reference.csv and work_precision.png (when matplotlib is available) to out_dir.
int work_precision_command(const WorkPrecisionOptions& app_options);

}  // namespace flexref::app
