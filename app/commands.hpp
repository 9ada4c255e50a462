#pragma once
/// \file commands.hpp
/// The `flexref` subcommands (docs/design/README.md). Each returns the process exit code; errors
/// are thrown and mapped to exit codes in main.cpp.
#include <memory>
#include <string>
#include <vector>

#include "app/default_model.hpp"
#include "app/work_limits.hpp"
#include "core/model.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "precision/precision.hpp"
#include "scene/scene.hpp"
#include "studies/convergence.hpp"
#include "studies/reference_precision.hpp"
#include "studies/reference_solver_name.hpp"
#include "studies/study_output.hpp"
#include "studies/study_record.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/reference_sidecar.hpp"

namespace flexref::app {

/// Exit codes: the one table of docs/cli.md ("Exit codes", the reasons in docs/decisions.md,
/// "Command line") and `flexref --help`.
inline constexpr int kExitOk = 0;
inline constexpr int kExitInputError = 1;   ///< bad scene, CSV, study file or option value
inline constexpr int kExitUsage = 2;        ///< command-line syntax (CLI11 parse errors)
inline constexpr int kExitSolverError = 3;  ///< an integrator failed (time, step, why)
inline constexpr int kExitRefused = 4;      ///< a study refused to report (uncertified, < 3 levels)
inline constexpr int kExitOutputError = 5;  ///< an output file or folder cannot be written

/// The exit-code table as `--help` prints it.
inline constexpr const char* kExitCodeTable =
    "Exit codes: 0 success, 1 bad input (scene, CSV, study file, option value), 2 usage "
    "(command-line syntax), 3 solver failure, 4 a study refused to report (e.g. an uncertified "
    "reference, fewer than three valid levels), 5 an output file or folder cannot be written. "
    "Interrupted by SIGINT, SIGTERM or SIGHUP, flexref removes its unfinished outputs and ends "
    "by the signal (shell status 128+N: 130, 143, 129).";

/// Refuses (core::InputError naming the scene file and the key) a scene whose physics double
/// precision cannot carry over [0, end_time]: a stiff mode (flexible body, contact, joint) or
/// an initial spin whose period is below core::smallest_resolved_step(end_time), a stiffness
/// or frequency that under- or overflows, an initial energy beyond 1e100 J.
void check_scene_extremes(const scene::Scene& scene, double end_time);
/// scene::read_scene followed by check_scene_extremes(scene, scene.end_time).
scene::Scene load_scene(const std::string& path,
                        core::FlexibleFormulation formulation = kDefaultFormulation);
/// core::output_times, refused (std::invalid_argument) beyond limits.max_rows rows before the
/// grid is built.
std::vector<double> limited_output_times(double end_time, double output_step,
                                         const WorkLimits& limits);
/// The coarsest step of a study: --dt when given, else the default dt or the scene's output
/// interval, the shorter (a step must divide the output interval: Andrews' squeezer writes every
/// 1e-4 s, so the default 1e-2 s could not run it).
double coarsest_step(double dt, bool dt_given, double output_step);
/// lie::validate_step_grid plus the step-count limit; `what` names the option ("--dt") in the
/// message. Returns the number of steps.
long check_scheme_run(const core::Model& model, double dt, const std::vector<double>& times,
                      const WorkLimits& limits, const std::string& what);
/// The output file of `run`, `reference` or `import-modes` and, when it gets one, its sidecar
/// (io::sidecar_path), checked before any work (io::OutputError): app/output_files.cpp.
void check_output_file(const std::string& output, bool with_sidecar);
/// Writes `record` as the sidecar of `output` (io::sidecar_path) or, when the output is
/// standard output, another descriptor, a device or a FIFO, says on stderr that none is written.
void write_sidecar(const studies::StudyRecord& record, const std::string& output);
/// Where a command's summary goes: standard error when its output file is standard output (so
/// that standard output carries the data alone), standard output otherwise.
std::ostream& summary_stream(const std::string& output);

struct CheckOptions {
  std::string scene;
  /// The model the scene is built with: a scene with joints at a flexible body's nodes loads
  /// only under the coupled model.
  core::FlexibleFormulation model = kDefaultFormulation;
};
int check_command(const CheckOptions& options);

/// `--model coupled|lte`: the formulation of flexible bodies' equations (rigid bodies are the
/// same in both), a command-line choice so that scenes stay model-agnostic. Returns the
/// core::FlexibleFormulation of the value; throws std::invalid_argument for any other.
core::FlexibleFormulation parse_formulation(const std::string& model);

/// The reference solver to use for a scene: `solver` itself, except that a model with flexible
/// bodies has no analytic solution — "exact" is refused (std::invalid_argument naming
/// `option`). "auto" stays "auto" (trajectory::resolve_reference_solver resolves it: never exact
/// for a flexible model).
studies::ReferenceSolver reference_solver_for(const core::Model& model,
                                              studies::ReferenceSolver solver,
                                              const std::string& option);

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

struct ReferenceOptions {
  std::string scene;
  core::FlexibleFormulation model = kDefaultFormulation;
  /// "auto": reference::choose_reference_solver (arkode's ESDIRK on a stiff oscillatory scene,
  /// else cvode; never the exact solution, which --solver exact asks for).
  studies::ReferenceSolver solver = studies::ReferenceSolver::kAuto;
  /// cvode: auto|adams|bdf|bdf2; ida: auto|bdf|bdf2; arkode: auto|erk|esdirk
  studies::ReferenceMethod method = studies::ReferenceMethod::kAuto;
  double rtol = 1e-10;
  bool rtol_given = false;  ///< else extended and quad use precision::default_rtol
  double atol = -1.0;
  bool estimate = true;
  std::string output;
  WorkLimits limits;
  /// double | extended | quad (docs/precision.md)
  flexref::precision::Precision precision = flexref::precision::Precision::kDouble;
};
int reference_command(const ReferenceOptions& options);
/// `reference --precision extended|quad` (app/high_precision_command.cpp).
int high_precision_reference_command(const ReferenceOptions& options);
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

/// Refuses (std::invalid_argument, exit 1) results of different scenes (trajectory::scene_mismatch)
/// unless `allow`; with `allow` a mismatch is a warning on standard error. Returns the mismatch
/// ("" when none).
std::string check_same_scene(const trajectory::SceneIdentity& a, const std::string& a_what,
                             const trajectory::SceneIdentity& b, const std::string& b_what,
                             bool allow);

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

/// The external methods of `converge` and `work-precision` (docs/external.md): `external`, a
/// command template run once per level, writing its files as `run_<label>_<level>.csv` into
/// the study's staging folder `out`; or `runs`, "DT=FILE" pairs of runs already made. Throws
/// std::invalid_argument for a malformed pair or label.
struct ExternalOptions {
  std::string scene;
  std::string external;
  std::vector<std::string> runs;
  std::string label;
  int claimed_order = 0;
  double timeout = 3600.0;
  /// The studied scene: a file whose sidecar (FILE.meta.toml) names another scene is refused
  /// (--runs: before any work, exit 1; --external: that level fails) unless
  /// allow_scene_mismatch (check_same_scene).
  trajectory::SceneIdentity scene_identity;
  bool allow_scene_mismatch = false;
};
std::vector<studies::ExternalMethod> external_methods(const ExternalOptions& options,
                                                      const studies::StudyOutput& out);

/// The identity a result of `scene` records in its sidecar (scene_record).
trajectory::SceneIdentity scene_identity(const std::string& scene_file, const scene::Scene& scene);

/// A result record (studies/study_record.hpp) that starts with the [scene] table: the scene
/// file, its name, the hash of its physics (scene/scene_identity.hpp), the creation time and
/// the model formulation (`model = "coupled"` or `"lte"`, the --model option).
studies::StudyRecord scene_record(const std::string& scene_file, const scene::Scene& scene);

}  // namespace flexref::app
