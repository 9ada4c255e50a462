/// \file main.cpp
/// The `flexref` command line (CLI11). Exit codes (one table: app/commands.hpp,
/// docs/decisions.md "Command line", the --help epilogue): 0 success, 1 bad input, 2 usage,
/// 3 solver failure, 4 a study refused to report, 5 an output cannot be written.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>

#include "app/cli_validators.hpp"
#include "app/commands.hpp"
#include "app/figure_command.hpp"
#include "app/import_modes_command.hpp"
#include "app/lte_map_command.hpp"
#include "app/modal_truncation_command.hpp"
#include "app/stability_command.hpp"
#include "app/work_precision_command.hpp"
#include "core/error.hpp"
#include "io/interrupt_cleanup.hpp"
#include "io/output_file.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/stepper.hpp"
#include "studies/mpi/distribution.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/study_refused.hpp"

namespace {

/// The output rule (io/output_file.hpp, docs/output.md "Where outputs go"), in the help of every
/// option that takes an output path.
constexpr const char* kOutputFileHelp =
    "file to write; - for standard output; a symbolic link's target is written, a FIFO or "
    "device directly (no .meta.toml sidecar then); docs/output.md";
constexpr const char* kOutputFolderHelp =
    "output directory, replaced as a whole when the study completes (a link to a folder stays "
    "a link; docs/output.md)";

/// genalpha's options (lie/genalpha_parameters.hpp, docs/schemes.md "Lie-group generalized-α"):
/// --rho-inf, its spectral radius at infinity, and --perturbed-start, Arnold's starting value
/// a_0 = v̇(t_0 + (α_m − α_f) h). Other schemes ignore them.
void add_genalpha_options(CLI::App* command, double& rho_inf, bool& perturbed_start) {
  command
      ->add_option("--rho-inf", rho_inf,
                   "genalpha's spectral radius at infinity, in [0, 1] (1: no numerical damping)")
      ->check(flexref::app::number_in(0.0, 1.0))
      ->capture_default_str();
  command->add_flag("--perturbed-start", perturbed_start,
                    "genalpha: start from a_0 = dv/dt(t0 + (alpha_m - alpha_f) h) (Arnold's "
                    "perturbed starting value) instead of a_0 = dv/dt(t0)");
}

/// A study's --reference-budget (docs/precision.md, "Cost guard").
void add_reference_budget(CLI::App* command, double& budget) {
  using flexref::app::non_negative_number;
  command
      ->add_option("--reference-budget", budget,
                   "seconds of wall time auto may spend on a quad reference; over it (projected "
                   "early), the study keeps the double one (0: no bound; docs/precision.md)")
      ->check(non_negative_number())
      ->capture_default_str();
}

/// --model of every command that takes it, with the one default (app/default_model.hpp).
void add_model_option(CLI::App* command, std::string& model) {
  command
      ->add_option("--model", model,
                   "flexible bodies' equations: coupled | lte (lte by default: the model the "
                   "schemes integrate)")
      ->check(CLI::IsMember({"coupled", "lte"}))
      ->capture_default_str();
}

/// --max-steps and --max-rows (app::WorkLimits): counts, whole numbers.
void add_limits(CLI::App* command, flexref::app::WorkLimits& limits, bool steps) {
  using flexref::app::positive_integer;
  if (steps) {
    command
        ->add_option("--max-steps", limits.max_steps,
                     "refuse a scheme run of more steps (raise it to allow longer runs)")
        ->check(positive_integer())
        ->capture_default_str();
  }
  command
      ->add_option("--max-rows", limits.max_rows,
                   "refuse a trajectory of more output rows (raise it to allow larger files)")
      ->check(positive_integer())
      ->capture_default_str();
}

/// --allow-scene-mismatch: compare files whose sidecars name different scenes
/// (docs/decisions.md, "Scene identity").
void add_allow_scene_mismatch(CLI::App* command, bool& allow) {
  command->add_flag("--allow-scene-mismatch", allow,
                    "compare results whose sidecars (FILE.meta.toml) name different scenes or "
                    "another version of the scene (refused otherwise)");
}

/// --estimate-factor of lte-map and modes: one meaning (trajectory/accuracy_check.hpp).
void add_estimate_factor(CLI::App* command, double& factor) {
  using flexref::app::number_in;
  command
      ->add_option("--estimate-factor", factor,
                   "accuracy check: every reference run is repeated at rtol divided by this "
                   "factor (tighter); their distance estimates the run's error")
      ->check(number_in(2.0, 1e6))
      ->capture_default_str();
}

std::string metric_help(const std::string& what) {
  std::string list;
  for (const std::string& m : flexref::trajectory::metric_names())
    list += (list.empty() ? "" : " | ") + m;
  return what + ": " + list;
}

}  // namespace

namespace {

int run_command_line(int argc, char** argv) {
  using namespace flexref::app;
  CLI::App app{
      "flexref: trusted reference solutions for rigid and flexible bodies in large rotation "
      "(with contact and joints), and the verification of time integrators against them"};
  app.require_subcommand(1);
  app.footer(kExitCodeTable);
  app.set_version_flag("--version", "flexref 0.1.0");

  CheckOptions check;
  auto* check_cmd = app.add_subcommand("check", "validate a scene and print its model");
  check_cmd->add_option("scene", check.scene, "scene file (TOML)")->required();
  add_model_option(check_cmd, check.model);

  RunOptions run;
  auto* run_cmd = app.add_subcommand("run", "integrate a scene with a Lie-group scheme");
  run_cmd->add_option("scene", run.scene, "scene file (TOML)")->required();
  run_cmd->add_option("--scheme", run.scheme, "c1 | c2 | nmb | genalpha")
      ->check(CLI::IsMember(flexref::lie::scheme_names()))
      ->capture_default_str();
  run_cmd->add_option("--dt", run.dt, "step [s]")->check(positive_number())->capture_default_str();
  run_cmd->add_option("-o,--output", run.output, std::string("CSV ") + kOutputFileHelp)->required();
  add_model_option(run_cmd, run.model);
  add_limits(run_cmd, run.limits, true);
  double rho_inf = flexref::lie::kDefaultRhoInfinity;  // one subcommand runs: one value
  bool perturbed_start = false;
  add_genalpha_options(run_cmd, rho_inf, perturbed_start);

  ReferenceOptions ref;
  auto* ref_cmd = app.add_subcommand("reference", "compute a reference solution");
  ref_cmd->add_option("scene", ref.scene, "scene file (TOML)")->required();
  ref_cmd
      ->add_option("--solver", ref.solver,
                   "auto (arkode's ESDIRK on a stiff oscillatory scene, else cvode) | ida | "
                   "cvode | arkode | odeint | exact")
      ->check(CLI::IsMember({"auto", "ida", "cvode", "arkode", "odeint", "exact"}))
      ->capture_default_str();
  ref_cmd
      ->add_option("--method", ref.method,
                   "cvode: auto (from the scene's stiff elements) | adams | bdf | bdf2 (BDF "
                   "orders 1-2); ida: auto | bdf | bdf2; arkode: auto | erk | esdirk")
      ->check(CLI::IsMember({"auto", "adams", "bdf", "bdf2", "erk", "esdirk"}))
      ->capture_default_str();
  ref_cmd
      ->add_option("--rtol", ref.rtol,
                   "relative tolerance (double >= 1e-15; default for extended 1e-16, quad 1e-28)")
      ->check(number_in(1e-32, 1e-1))
      ->capture_default_str();
  ref_cmd->add_option("--atol", ref.atol, "absolute tolerance (default: = rtol)")
      ->check(number_in(1e-16, 1.0));
  ref_cmd->add_flag("!--no-estimate", ref.estimate,
                    "skip the error estimate (rerun 100x tighter and a second solver)");
  ref_cmd->add_option("-o,--output", ref.output, std::string("CSV ") + kOutputFileHelp)->required();
  add_model_option(ref_cmd, ref.model);
  ref_cmd
      ->add_option("--precision", ref.precision,
                   "double | extended (80-bit long double) | quad (binary128): the arithmetic of "
                   "the reference (docs/precision.md; extended and quad carry every scene: "
                   "rigid and flexible bodies, loads, potentials, contacts, gap supports and "
                   "joints)")
      ->check(CLI::IsMember({"double", "extended", "quad"}))
      ->capture_default_str();
  add_limits(ref_cmd, ref.limits, false);

  CompareOptions cmp;
  auto* cmp_cmd = app.add_subcommand("compare", "error norms of a run against a reference");
  cmp_cmd->add_option("run", cmp.run, "CSV of the run")->required();
  cmp_cmd->add_option("reference", cmp.reference, "CSV of the reference")->required();
  cmp_cmd->add_option("--metric", cmp.metric, metric_help("metric for the summary line"))
      ->check(CLI::IsMember(flexref::trajectory::metric_names()))
      ->capture_default_str();
  cmp_cmd->add_flag("--json", cmp.json, "print the comparison as JSON");
  add_allow_scene_mismatch(cmp_cmd, cmp.allow_scene_mismatch);
  cmp_cmd
      ->add_option("--time-tolerance", cmp.time_tolerance,
                   "row times match output times within this x the output step")
      ->check(number_in(0.0, 0.5))
      ->capture_default_str();
  cmp_cmd
      ->add_option("--euler-tolerance", cmp.euler_tolerance,
                   "largest accepted | |theta| - 1 | of Euler parameters")
      ->check(number_in(0.0, 0.1))
      ->capture_default_str();

  ConvergeOptions conv;
  auto* conv_cmd = app.add_subcommand("converge", "observed orders of convergence");
  conv_cmd->add_option("scene", conv.scene, "scene file (TOML)")->required();
  conv_cmd->add_option("--schemes", conv.schemes, "comma-separated list")
      ->delimiter(',')
      ->check(CLI::IsMember(flexref::lie::scheme_names()))
      ->capture_default_str();
  conv_cmd
      ->add_option("--dt", conv.dt,
                   "coarsest step [s]; by default 0.01 or the scene's output interval, the shorter")
      ->check(positive_number())
      ->capture_default_str();
  conv_cmd
      ->add_option("--levels", conv.levels,
                   "number of levels: steps dt, dt/2, ..., dt/2^(levels-1); an order is fitted "
                   "from at least 3 valid levels")
      ->check(integer_in(3, 16))
      ->capture_default_str();
  conv_cmd->add_option("--metric", conv.metric, metric_help("error metric"))
      ->check(CLI::IsMember(flexref::trajectory::metric_names()))
      ->capture_default_str();
  conv_cmd
      ->add_option("--reference-solver", conv.reference_solver,
                   "auto | ida | cvode | arkode | odeint | exact")
      ->check(CLI::IsMember({"auto", "ida", "cvode", "arkode", "odeint", "exact"}))
      ->capture_default_str();
  conv_cmd->add_option("--reference-rtol", conv.reference_rtol, "reference tolerance")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  conv_cmd->add_option("--jobs", conv.jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  conv_cmd->add_option("--out", conv.out_dir, kOutputFolderHelp)->capture_default_str();
  add_genalpha_options(conv_cmd, rho_inf, perturbed_start);
  add_model_option(conv_cmd, conv.model);
  conv_cmd
      ->add_option("--reference-precision", conv.reference_precision,
                   "auto (double; quad when double cannot certify every level and the scene "
                   "allows it) | double | extended | quad (docs/precision.md)")
      ->check(CLI::IsMember({"auto", "double", "extended", "quad"}))
      ->capture_default_str();
  add_reference_budget(conv_cmd, conv.reference_budget);
  add_limits(conv_cmd, conv.limits, true);
  auto* conv_external =
      conv_cmd->add_option("--external", conv.external,
                           "another code's integrator: a command with {scene}, {dt}, {output}, "
                           "run once per level (docs/external.md)");
  conv_cmd
      ->add_option("--runs", conv.runs, "runs already made, as DT=FILE pairs (docs/external.md)")
      ->excludes(conv_external);
  conv_cmd->add_option("--label", conv.label, "name of the external method in the table");
  conv_cmd->add_option("--order", conv.claimed_order, "the external method's claimed order")
      ->check(integer_in(1, 20));
  conv_cmd->add_option("--timeout", conv.timeout, "seconds per external run (0: no limit)")
      ->check(non_negative_number())
      ->capture_default_str();
  add_allow_scene_mismatch(conv_cmd, conv.allow_scene_mismatch);

  WorkPrecisionOptions wp;
  auto* wp_cmd = app.add_subcommand("work-precision", "error against CPU time, cheapest method");
  wp_cmd->add_option("scene", wp.scene, "scene file (TOML)")->required();
  wp_cmd->add_option("--schemes", wp.schemes, "comma-separated list")
      ->delimiter(',')
      ->check(CLI::IsMember(flexref::lie::scheme_names()))
      ->capture_default_str();
  wp_cmd
      ->add_option("--dt", wp.dt,
                   "coarsest step [s]; by default 0.01 or the scene's output interval, the shorter")
      ->check(positive_number())
      ->capture_default_str();
  wp_cmd->add_option("--levels", wp.levels, "number of steps: dt, dt/2, ..., dt/2^(levels-1)")
      ->check(integer_in(1, 16))
      ->capture_default_str();
  wp_cmd->add_option("--solvers", wp.solvers, "comma-separated list")
      ->delimiter(',')
      ->check(CLI::IsMember({"ida", "cvode", "arkode", "odeint"}))
      ->capture_default_str();
  wp_cmd->add_option("--tolerances", wp.tolerances, "comma-separated relative tolerances")
      ->delimiter(',')
      ->check(number_in(1e-14, 1e-1))
      ->capture_default_str();
  wp_cmd->add_option("--repeats", wp.repeats, "CPU time: minimum over this many runs")
      ->check(integer_in(1, 100))
      ->capture_default_str();
  wp_cmd->add_option("--metric", wp.metric, metric_help("error metric"))
      ->check(CLI::IsMember(flexref::trajectory::metric_names()))
      ->capture_default_str();
  wp_cmd
      ->add_option("--reference-solver", wp.reference_solver,
                   "auto | ida | cvode | arkode | odeint | exact")
      ->check(CLI::IsMember({"auto", "ida", "cvode", "arkode", "odeint", "exact"}))
      ->capture_default_str();
  wp_cmd->add_option("--reference-rtol", wp.reference_rtol, "reference tolerance")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  wp_cmd
      ->add_option("--jobs", wp.jobs,
                   "parallel runs (0: all cores); timings are per-thread CPU time, cleanest "
                   "with --jobs 1")
      ->check(integer_in(0, 1024));
  wp_cmd->add_option("--out", wp.out_dir, kOutputFolderHelp)->capture_default_str();
  add_genalpha_options(wp_cmd, rho_inf, perturbed_start);
  wp_cmd->add_option("--external", wp.external,
                     "another code's integrator: a command with {scene}, {dt}, {output}, run "
                     "per step; its CPU time is the program's own (docs/external.md)");
  wp_cmd->add_option("--label", wp.label, "name of the external method in the table");
  wp_cmd->add_option("--timeout", wp.timeout, "seconds per external run (0: no limit)")
      ->check(non_negative_number())
      ->capture_default_str();
  add_allow_scene_mismatch(wp_cmd, wp.allow_scene_mismatch);
  add_model_option(wp_cmd, wp.model);
  wp_cmd
      ->add_option("--reference-precision", wp.reference_precision,
                   "auto (double; quad when double cannot certify every run and the scene "
                   "allows it) | double | extended | quad (docs/precision.md)")
      ->check(CLI::IsMember({"auto", "double", "extended", "quad"}))
      ->capture_default_str();
  add_reference_budget(wp_cmd, wp.reference_budget);
  add_limits(wp_cmd, wp.limits, true);

  StabilityCommandOptions stab;
  auto* stab_cmd =
      app.add_subcommand("stability",
                         "largest stable step vs spin rate, inertia ratio, modal frequency or "
                         "contact stiffness");
  stab_cmd->add_option("scene", stab.scene,
                       "optional scene: first free body's inertia and W0 direction");
  stab_cmd
      ->add_option("--parameter", stab.parameter,
                   "spin | inertia_ratio | modal_frequency | contact_stiffness")
      ->check(CLI::IsMember({"spin", "inertia_ratio", "modal_frequency", "contact_stiffness"}))
      ->capture_default_str();
  auto* values_opt =
      stab_cmd
          ->add_option("--values", stab.values,
                       "swept values (comma-separated): spin rad/s > 0, inertia_ratio J3/J1 >= 1, "
                       "modal_frequency rad/s > 0, contact_stiffness N/m > 0")
          ->delimiter(',')
          ->check(positive_number());
  stab_cmd
      ->add_option("--min", stab.min,
                   "log-spaced range start (default: spin 0.1, inertia_ratio 1, modal_frequency "
                   "10, contact_stiffness 1e3)")
      ->check(positive_number())
      ->excludes(values_opt);
  stab_cmd
      ->add_option("--max", stab.max,
                   "log-spaced range end (default: spin 1000, inertia_ratio 1e6, "
                   "modal_frequency 1e4, contact_stiffness 1e9)")
      ->check(positive_number())
      ->excludes(values_opt);
  stab_cmd->add_option("--count", stab.count, "number of values")
      ->check(integer_in(1, 200))
      ->capture_default_str();
  stab_cmd->add_option("--schemes", stab.schemes, "comma-separated list")
      ->delimiter(',')
      ->check(CLI::IsMember(flexref::lie::scheme_names()))
      ->capture_default_str();
  stab_cmd
      ->add_option("--spin", stab.spin,
                   "|W0| for the ratio sweep and degenerate set (0: the body's) [rad/s]")
      ->check(non_negative_number());
  stab_cmd->add_option("--steps", stab.steps, "steps per stability run")
      ->check(integer_in(10L, 100000000L))
      ->capture_default_str();
  stab_cmd
      ->add_option("--energy-factor", stab.energy_factor,
                   "unstable when |dE| > f|E0| (and |dpi| > f|pi0|)")
      ->check(positive_number())
      ->capture_default_str();
  stab_cmd->add_option("--rtol", stab.rtol, "bisection relative tolerance")
      ->check(number_in(1e-8, 0.5))
      ->capture_default_str();
  stab_cmd->add_flag("--degenerate,!--no-degenerate", stab.degenerate,
                     "run the degenerate-body set");
  stab_cmd->add_option("--long-run-steps", stab.long_run_steps, "0: no long run")
      ->check(integer_in(0, 1000000000000L))
      ->capture_default_str();
  stab_cmd->add_option("--long-run-dt", stab.long_run_dt, "long-run step [s]")
      ->check(positive_number())
      ->capture_default_str();
  stab_cmd->add_option("--jobs", stab.jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  stab_cmd->add_option("--out", stab.out_dir, kOutputFolderHelp)->capture_default_str();
  add_genalpha_options(stab_cmd, rho_inf, perturbed_start);
  add_limits(stab_cmd, stab.limits, true);

  FigureCommandOptions fig;
  auto* fig_cmd = app.add_subcommand(
      "figure", "trajectory of a tracked point by each scheme and step, with the reference");
  fig_cmd->add_option("study", fig.study, "study file (TOML), e.g. studies/paper/*.toml")
      ->required();
  fig_cmd->add_option("--jobs", fig.jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  fig_cmd
      ->add_option("--reference-precision", fig.reference_precision,
                   "auto (quad when the double reference cannot certify a curve and the scene "
                   "allows it) | double | extended | quad (docs/precision.md)")
      ->check(CLI::IsMember({"auto", "double", "extended", "quad"}))
      ->capture_default_str();
  add_reference_budget(fig_cmd, fig.reference_budget);
  fig_cmd->add_option("--out", fig.out_dir, kOutputFolderHelp)->capture_default_str();
  add_limits(fig_cmd, fig.limits, true);

  LteMapCommandOptions lte;
  auto* lte_cmd = app.add_subcommand(
      "lte-map", "LTE model error vs coupled model over spin ratio and inertia ratio");
  lte_cmd->add_option("scene", lte.scene, "scene file with a free flexible body (TOML)")
      ->required();
  auto* lte_spins =
      lte_cmd
          ->add_option("--spin-ratios", lte.spin_ratios, "Omega0/omega1 values (comma-separated)")
          ->delimiter(',')
          ->check(positive_number());
  lte_cmd->add_option("--spin-min", lte.spin_min, "log-spaced spin ratios: first")
      ->check(positive_number())
      ->excludes(lte_spins)
      ->capture_default_str();
  lte_cmd->add_option("--spin-max", lte.spin_max, "log-spaced spin ratios: last")
      ->check(positive_number())
      ->excludes(lte_spins)
      ->capture_default_str();
  lte_cmd->add_option("--spin-count", lte.spin_count, "log-spaced spin ratios: count")
      ->excludes(lte_spins)
      ->check(integer_in(1, 200))
      ->capture_default_str();
  auto* lte_inertias = lte_cmd
                           ->add_option("--inertia-ratios", lte.inertia_ratios,
                                        "I_flex/I_rigid values (comma-separated)")
                           ->delimiter(',')
                           ->check(positive_number());
  lte_cmd->add_option("--inertia-min", lte.inertia_min, "log-spaced inertia ratios: first")
      ->check(positive_number())
      ->excludes(lte_inertias)
      ->capture_default_str();
  lte_cmd->add_option("--inertia-max", lte.inertia_max, "log-spaced inertia ratios: last")
      ->check(positive_number())
      ->excludes(lte_inertias)
      ->capture_default_str();
  lte_cmd->add_option("--inertia-count", lte.inertia_count, "log-spaced inertia ratios: count")
      ->excludes(lte_inertias)
      ->check(integer_in(1, 200))
      ->capture_default_str();
  lte_cmd->add_option("--solver", lte.solver, "reference solver: cvode | ida | odeint")
      ->check(CLI::IsMember({"cvode", "ida", "odeint"}))
      ->capture_default_str();
  lte_cmd->add_option("--rtol", lte.rtol, "reference tolerance (both models)")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  add_estimate_factor(lte_cmd, lte.estimate_factor);
  lte_cmd->add_flag("!--no-scale-loads", lte.scale_loads,
                    "keep the loads (default: scale them with spin and inertia)");
  lte_cmd
      ->add_option("--truth", lte.truth,
                   "the truth: stiffened (coupled with geometric stiffening) | coupled (the "
                   "classical coupled model) | auto (stiffened when the body can be)")
      ->check(CLI::IsMember({"auto", "stiffened", "coupled"}))
      ->capture_default_str();
  lte_cmd->add_option("--point", lte.point, "tracked node point (default: farthest node)");
  lte_cmd->add_option("--end-time", lte.end_time, "s (default: the scene's)")
      ->check(positive_number());
  lte_cmd->add_option("--jobs", lte.jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  lte_cmd->add_option("--out", lte.out_dir, kOutputFolderHelp)->capture_default_str();
  add_limits(lte_cmd, lte.limits, false);

  ImportModesOptions import_modes;
  auto* import_cmd = add_import_modes_command(app, import_modes);

  ModalTruncationCommandOptions modes;
  auto* modes_cmd = app.add_subcommand(
      "modes", "reference tip deflection and attitude vs the number of retained modes");
  modes_cmd->add_option("scene", modes.scene, "scene file with a flexible body (TOML)")->required();
  modes_cmd
      ->add_option("--modes", modes.modes, "mode counts (comma-separated; largest = reference)")
      ->delimiter(',')
      ->check(integer_in(1, 100000))
      ->capture_default_str();
  modes_cmd->add_option("--body", modes.body, "flexible body (default: the first)");
  modes_cmd->add_option("--point", modes.point, "tracked node point (default: farthest node)");
  modes_cmd->add_option("--solver", modes.solver, "reference solver: odeint | cvode | ida")
      ->check(CLI::IsMember({"odeint", "cvode", "ida"}))
      ->capture_default_str();
  modes_cmd->add_option("--rtol", modes.rtol, "reference tolerance")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  add_estimate_factor(modes_cmd, modes.estimate_factor);
  modes_cmd->add_option("--end-time", modes.end_time, "s (default: the scene's)")
      ->check(positive_number());
  add_model_option(modes_cmd, modes.model);
  modes_cmd->add_option("--jobs", modes.jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  modes_cmd->add_option("--out", modes.out_dir, kOutputFolderHelp)->capture_default_str();

  // An unknown command is a usage error that names it (CLI11 would say "A subcommand is
  // required").
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::fprintf(stderr, "flexref: unknown command '%s'; the commands are %s (flexref --help)\n",
                   argv[1], names.c_str());
      return kExitUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every parse error is a usage error (CLI11's own codes,
    // 105, 106 …, are not part of the table).
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }

  try {
    flexref::lie::set_genalpha_rho_inf(rho_inf);
    flexref::lie::set_genalpha_perturbed_start(perturbed_start);
    if (*check_cmd) return check_command(check);
    if (*run_cmd) return run_command(run);
    if (*ref_cmd) {
      ref.rtol_given = ref_cmd->count("--rtol") > 0;
      return reference_command(ref);
    }
    if (*cmp_cmd) return compare_command(cmp);
    if (*conv_cmd) {
      conv.schemes_given = conv_cmd->count("--schemes") > 0;
      conv.dt_given = conv_cmd->count("--dt") > 0;
      return converge_command(conv);
    }
    if (*wp_cmd) {
      wp.dt_given = wp_cmd->count("--dt") > 0;
      return work_precision_command(wp);
    }
    if (*stab_cmd) return stability_command(stab);
    if (*lte_cmd) return lte_map_command(lte);
    if (*fig_cmd) return figure_command(fig);
    if (*import_cmd) return import_modes_command(import_modes);
    if (*modes_cmd) return modal_truncation_command(modes);
  } catch (const flexref::core::InputError& e) {
    std::fprintf(stderr, "flexref: error: %s\n", e.what());
    return kExitInputError;
  } catch (const flexref::core::SolverError& e) {
    std::fprintf(stderr, "flexref: solver error: %s\n", e.what());
    return kExitSolverError;
  } catch (const flexref::trajectory::StudyRefused& e) {
    std::fprintf(stderr, "flexref: refused: %s\n", e.what());
    return kExitRefused;
  } catch (const flexref::io::OutputError& e) {
    std::fprintf(stderr, "flexref: output error: %s\n", e.what());
    return kExitOutputError;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "flexref: output error: %s\n", e.what());
    return kExitOutputError;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "flexref: error: %s\n", e.what());
    return kExitInputError;
  } catch (const std::exception& e) {
    // Anything else happened while computing (no input or output error type reached here).
    std::fprintf(stderr, "flexref: failure: %s\n", e.what());
    return kExitSolverError;
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  // First, before any thread exists: SIGINT, SIGTERM and SIGHUP remove the unfinished outputs
  // (io/interrupt_cleanup.hpp).
  flexref::io::install_interrupt_cleanup();
  // One process, or a rank of an MPI job (studies/mpi/distribution.hpp, docs/mpi.md).
  flexref::studies::ProcessSession session(argc, argv);
  return session.finish(run_command_line(argc, argv));
}
