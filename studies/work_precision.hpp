#pragma once
/// \file work_precision.hpp
/// The `work-precision` study (docs/design/studies.md): the speed/accuracy trade. Each scheme at
/// steps h0, h0/2, …, and each reference solver at relative tolerances 1e-3 … 1e-12, gives an
/// error against a certified reference (in a named metric) and a CPU time; the summary names,
/// for each target error, the cheapest method that reaches it.
///
/// CPU time is the calling thread's CPU time (CLOCK_THREAD_CPUTIME_ID) of the integration
/// only — lie::run_scheme or reference::solve_reference, never tabulation or output — and the
/// minimum over `repeats` runs, which filters out preemption and cache effects. Runs execute in
/// parallel on `jobs` threads: the errors do not depend on `jobs`, the timings do (threads on a
/// small machine share caches and memory bandwidth), so `jobs = 1` gives the cleanest timings.
///
/// Errors below 100× the reference's estimated error cannot be measured: those runs are
/// "uncertified" and take no part in the cheapest-method summary.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "studies/convergence.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::studies {

struct WorkPrecisionOptions {
  std::vector<std::string> schemes = lie::default_scheme_names();
  /// The options every scheme's stepper is built with (genalpha's ρ∞ and perturbed start, a
  /// user method's named values; lie/method_options.hpp).
  lie::MethodOptions method_options;
  double h0 = 1e-2;  ///< coarsest step [s]
  int levels = 6;    ///< steps h0, h0/2, …, h0/2^(levels−1)
  std::vector<std::string> solvers{"ida", "cvode", "arkode", "odeint"};
  std::vector<double> tolerances{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  int repeats = 3;  ///< CPU time is the minimum over this many runs
  std::string metric = trajectory::kDefaultMetric;
  std::string reference_solver = "auto";
  double reference_rtol = 1e-12;
  int jobs = 1;
  bool progress = false;  ///< progress line on stderr
  /// Other codes' integrators (studies/convergence.hpp), after the solvers; their CPU time is
  /// the one ExternalLevel reports (a program's own, from wait4), minimum over the repeats.
  std::vector<ExternalMethod> external;
  /// A reference computed by the caller (extended or quad precision,
  /// precision/high_precision_reference.hpp) instead of reference_solver's.
  std::shared_ptr<const trajectory::CertifiedReference> given_reference;
};

/// One point of the work-precision diagram.
struct WorkPrecisionRun {
  std::string method;        ///< scheme ("c1", "c2", "nmb"), solver ("ida", …) or label
  std::string kind;          ///< "scheme", "solver" or "external"
  double setting = 0.0;      ///< step h [s] for a scheme, relative tolerance for a solver
  double error = 0.0;        ///< metric against the reference (+inf when failed)
  double cpu_seconds = 0.0;  ///< minimum thread CPU time over the repeats (NaN when failed)
  /// "ok", "uncertified", "off-joints" (an external run off its scene's ideal joints), "unstable"
  /// (a scheme run that breaks the scene's invariants,
  /// core/invariants.hpp), "saturated" (an error of kSaturationFraction of the metric's largest
  /// value or more, trajectory/error_metrics.hpp), or "failed: why".
  std::string status;
  /// Right-hand-side (residual) evaluations of a solver run, the cost that does not depend on
  /// the machine; 0 for a scheme.
  long evaluations = 0;
  /// An external run's cpu_seconds is the program's own report of its integration.
  bool cpu_reported = false;
  /// With ideal joints: the run's largest joint violation from its positions (m or rad,
  /// trajectory/joint_violation.hpp); NaN when not measured. An external run off its joints
  /// has the status "off-joints" and is left out of the cheapest-method table.
  double violation = std::numeric_limits<double>::quiet_NaN();
};

/// The cheapest run reaching a target error (see cheapest_methods).
struct CheapestMethod {
  double target = 0.0;
  bool found = false;  ///< false: no "ok" run has error ≤ target ("none reaches it")
  WorkPrecisionRun run;
};

struct WorkPrecisionResult {
  WorkPrecisionOptions options;
  trajectory::CertifiedReference reference;
  /// schemes × levels, then solvers × tolerances, then external methods × levels
  std::vector<WorkPrecisionRun> runs;
  std::vector<CheapestMethod> cheapest;
  /// The cheapest reference solver run per reference_target_errors() (solver runs only).
  std::vector<CheapestMethod> cheapest_references;
  std::vector<std::string> notes;
};

/// The target errors of the summary table: 1e-2, 1e-4, 1e-6, 1e-8.
std::vector<double> default_target_errors();
/// The target errors of the reference solvers' summary: 1e-4, 1e-6, 1e-8, 1e-10, 1e-12.
std::vector<double> reference_target_errors();

/// For each target, the run with the smallest CPU time among the runs with status "ok" and
/// error ≤ target (ties: the first in `runs` order).
std::vector<CheapestMethod> cheapest_methods(const std::vector<WorkPrecisionRun>& runs,
                                             const std::vector<double>& targets);

/// Throws std::invalid_argument, before any work, for bad options: an unknown scheme or solver, a
/// scheme that refuses the model (the coupled model of a flexible body), a level whose step does
/// not fit the output grid. run_work_precision calls it before its reference; a command that
/// computes a reference itself (--reference-precision) calls it first.
void check_work_precision_inputs(const core::Model& model, const std::vector<double>& output_times,
                                 const WorkPrecisionOptions& options);

/// Runs the study; throws std::invalid_argument for bad options and like the solvers when the
/// reference fails. A failing scheme or solver run is recorded as "failed: why".
WorkPrecisionResult run_work_precision(const core::Model& model,
                                       const std::vector<double>& output_times,
                                       const WorkPrecisionOptions& options);

/// The terminal table: one block per method (setting, error, CPU time, status), then the
/// cheapest method per target error, the cheapest reference solver per target error, then the
/// notes.
std::string format_work_precision_table(const WorkPrecisionResult& result);
/// CSV: method,kind,setting,error,cpu_seconds,status,evaluations.
std::string work_precision_csv(const WorkPrecisionResult& result);

}  // namespace flexref::studies
