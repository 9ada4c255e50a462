#pragma once
/// \file stability_command.hpp
/// `flexref stability`: largest stable step of each scheme against spin rate or inertia ratio
/// on a torque-free body, the degenerate-body set and long-run drifts (studies/stability.hpp).
#include <string>
#include <vector>

#include "app/work_limits.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "studies/stability_parameter.hpp"

namespace flexref::app {

struct StabilityCommandOptions {
  /// Optional scene: its first free body's inertia and W0 direction replace free_spin's.
  std::string scene;
  /// "spin" (|W0|, rad/s), "inertia_ratio" (J3/J1), "modal_frequency" (ω_max, rad/s; default
  /// 10 … 1e4) or "contact_stiffness" (k, N/m; default 1e3 … 1e9) — the last two on built-in
  /// linear models with the limit 2/ω (studies/stability_sweeps.hpp).
  studies::StabilityParameter parameter = studies::StabilityParameter::kSpin;
  /// Swept values; when empty, `count` values spaced logarithmically in [min, max]; min and
  /// max ≤ 0 mean the parameter's default range: spin 0.1 … 1000 rad/s, ratio 1 … 1e6.
  std::vector<double> values;
  double min = 0.0;
  double max = 0.0;
  int count = 9;
  std::vector<std::string> schemes = lie::default_scheme_names();
  lie::MethodOptions method_options;  ///< --rho-inf, --perturbed-start
  double spin = 0.0;           ///< |W0| of the ratio sweep and degenerate set (0: the body's)
  long steps = 1000;           ///< steps per stability run
  double energy_factor = 0.5;  ///< unstable when |E − E0| > factor·|E0| (same for |π|)
  double rtol = 1e-3;          ///< bisection relative tolerance
  bool degenerate = true;      ///< run the built-in degenerate bodies
  long long_run_steps = 1000000;
  double long_run_dt = 0.01;  ///< s
  int jobs = 0;               ///< 0: all cores
  std::string out_dir = "out/stability";
  WorkLimits limits;  ///< --max-steps bounds --long-run-steps and --steps
};

int stability_command(const StabilityCommandOptions& options);

}  // namespace flexref::app
