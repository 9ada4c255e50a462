#pragma once
/// \file convergence.hpp
/// The `converge` study (docs/design/studies.md): each scheme at steps h0, h0/2, …, its error
/// against a certified reference in a named metric, pairwise and least-squares observed
/// orders. Only levels that measure the scheme's asymptotic error enter the fit; the others are
/// marked and the table says why: a step above the scene's explicit step limit
/// (core::explicit_step_limit: central differences on a mode or penalty element are unstable
/// there), a run that breaks the scene's invariants ("unstable", core/invariants.hpp), an error
/// that is a sizeable fraction of the largest the metric can give ("saturated",
/// trajectory/error_metrics.hpp), an error that does not decrease from the previous valid level,
/// an error not at least 100× the reference's estimated error ("uncertified"), an error at
/// round-off (which also stops the refinement), or an external run that is off its scene's
/// ideal joints ("off-joints", trajectory/joint_violation.hpp: a joint violated by more than a
/// small fraction of the run's own error at it, or a jointed body without pose columns). No order
/// is fitted from fewer than three valid levels (two points always lie on a line: their "order"
/// verifies nothing).
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/step_limit.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_contract.hpp"

namespace flexref::studies {

/// One level of an integrator outside the method registry: its trajectory under the contract
/// (docs/external.md) and the CPU time it took (NaN when unknown, e.g. a run made earlier).
struct ExternalLevel {
  trajectory::RunData run;
  double cpu_seconds = 0.0;
  /// cpu_seconds is the program's own report of its integration (`# cpu_seconds`), not the
  /// whole process's CPU time.
  bool cpu_reported = false;
};

/// An integrator outside the method registry (another program, runs already made): studied
/// like a registered scheme, its errors measured under the trajectory contract.
struct ExternalMethod {
  std::string label;      ///< its name in tables (letters, digits, '_', '-')
  int claimed_order = 0;  ///< 0: no claim
  /// The steps of its levels; empty: the study's h0, h0/2, … (`levels` of them).
  std::vector<double> steps;
  /// Produces the level with step h (level 0 is the coarsest); throws to fail that level only.
  std::function<ExternalLevel(double h, int level)> run;
  /// Where the run of level `level` keeps its output file (empty: nothing kept, as for runs
  /// made earlier). A level run on another MPI rank sends the file's bytes to rank 0, which
  /// writes them here, so the study folder is the same for any number of ranks (docs/mpi.md).
  std::function<std::string(int level)> kept_file;
};

/// On a rank other than 0: the bytes of `method`'s kept file of `level`, to send to rank 0;
/// empty on rank 0 or when the method keeps nothing.
std::string kept_file_bytes(const ExternalMethod& method, int level);
/// On rank 0: writes `bytes` received from another rank to method.kept_file(level) (nothing
/// when `bytes` is empty). Throws io::OutputError when the file cannot be written.
void restore_kept_file(const ExternalMethod& method, int level, const std::string& bytes);

struct ConvergenceOptions {
  std::vector<std::string> schemes = lie::default_scheme_names();
  /// The options every scheme's stepper is built with (genalpha's ρ∞ and perturbed start, a
  /// user method's named values; lie/method_options.hpp).
  lie::MethodOptions method_options;
  double h0 = 1e-2;
  int levels = 6;
  std::string metric = trajectory::kDefaultMetric;
  std::string reference_solver = "auto";
  double reference_rtol = 1e-12;
  int jobs = 1;
  bool progress = false;                 ///< progress line on stderr
  std::vector<ExternalMethod> external;  ///< studied after the schemes
  /// A reference computed by the caller (e.g. in extended or quad precision,
  /// precision/high_precision_reference.hpp) instead of reference_solver's; its estimate must
  /// be in `metric`.
  std::shared_ptr<const trajectory::CertifiedReference> given_reference;
};

struct ConvergenceLevel {
  std::string scheme;
  double h = 0.0;
  long steps = 0;
  double error = 0.0;
  double order = 0.0;  ///< pairwise order against the previous level (NaN for the first)
  double cpu_seconds = 0.0;
  /// "ok", "above step limit", "unstable", "saturated", "not decreasing", "uncertified",
  /// "round-off", or "failed: why".
  std::string status;
  /// The error as a fraction of its bound (trajectory/error_metrics.hpp, metric_saturation): at
  /// kSaturationFraction or more the level is "saturated".
  double saturation = 0.0;
  /// With ideal joints: the largest violation Φ of a joint (m or rad, trajectory/
  /// joint_violation.hpp) measured from the run's positions, NaN when not measured (no joints,
  /// a failed run, or a run without a jointed body's pose columns); each joint's in `joints`.
  double violation = std::numeric_limits<double>::quiet_NaN();
  std::string joints;
};

struct SchemeSummary {
  std::string scheme;
  int claimed_order = 0;
  double fitted_order = 0.0;  ///< least squares over the "ok" levels (NaN if < 3)
  int fitted_levels = 0;      ///< the "ok" levels
  bool refused() const { return fitted_levels < kMinFittedLevels; }
  /// The fewest valid levels an order is fitted from.
  static constexpr int kMinFittedLevels = 3;
};

struct ConvergenceResult {
  ConvergenceOptions options;
  trajectory::CertifiedReference reference;
  core::StepLimit step_limit;  ///< the model's explicit step limit (unbounded: rigid only)
  std::vector<ConvergenceLevel> levels;
  std::vector<SchemeSummary> summaries;
  std::vector<std::string> notes;
  /// The scene has ideal joints: every level's violation is measured (the table shows it).
  bool joints = false;
  /// True when a scheme has no fitted order (fewer than three valid levels): the study
  /// refuses to report an order for it (exit code 4).
  bool refused() const;
};

/// Throws std::invalid_argument, before any work, when a scheme refuses the model (e.g. the
/// coupled model of a flexible body), a level's step does not fit the output grid
/// (lie::validate_step_grid), fewer than three levels are asked for, or an external method
/// has no runner or fewer than three steps. run_convergence calls it before the reference.
void check_convergence_inputs(const core::Model& model, const std::vector<double>& output_times,
                              const ConvergenceOptions& options);

ConvergenceResult run_convergence(const core::Model& model, const std::vector<double>& output_times,
                                  const ConvergenceOptions& options);

/// The analysis of one method's levels (coarsest first, error, saturation and status "ok",
/// "unstable" or "failed: …" set). Only levels that measure the method's asymptotic error stay
/// "ok": a step above `step_limit` (the model's explicit step limit for the built-in schemes;
/// unbounded for an external method) is "above step limit", an error at kSaturationFraction of
/// its bound or more "saturated", an error that does not decrease from the previous valid level
/// "not decreasing", an error at round-off "round-off" (and stops the refinement), an error not
/// kCertificationFactor× above the reference's estimated error "uncertified".
/// Pairwise orders are filled in; the least-squares order is fitted over the "ok" levels, and
/// refused (NaN) from fewer than three. Notes say what was left out and why.
SchemeSummary summarize_levels(const std::string& method, int claimed_order,
                               std::vector<ConvergenceLevel>& levels, double reference_estimate,
                               const core::StepLimit& step_limit, std::vector<std::string>& notes);

/// The terminal table (errors, pairwise orders, fitted orders, notes).
std::string format_convergence_table(const ConvergenceResult& result);
/// CSV: scheme,h,steps,error,order,cpu_seconds,status.
std::string convergence_csv(const ConvergenceResult& result);

}  // namespace flexref::studies
