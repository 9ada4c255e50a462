#include "app/work_precision_command.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/external_methods.hpp"
#include "app/help_text.hpp"
#include "app/input_checks.hpp"
#include "app/scene_metadata.hpp"
#include "core/output_times.hpp"
#include "lie/stepper.hpp"
#include "scene/scene_reader.hpp"
#include "studies/high_precision_references.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/reference_policy.hpp"
#include "studies/reference_record.hpp"
#include "studies/study_output.hpp"
#include "studies/work_precision.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
int work_precision_command(const WorkPrecisionOptions& app_options) {
  const scene::Scene scene = load_scene(app_options.scene, app_options.model);
  const core::Model& model = *scene.model;
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, app_options.limits);

  studies::WorkPrecisionOptions study;
  study.schemes = app_options.schemes;
  study.method_options = app_options.method_options;
  study.h0 = coarsest_step(app_options.dt, app_options.dt_given, scene.output_step);
  study.levels = app_options.levels;
  study.solvers = app_options.solvers;
  study.tolerances = app_options.tolerances;
  study.repeats = app_options.repeats;
  study.metric = app_options.metric;
  study.reference_solver = studies::to_string(
      reference_solver_for(model, app_options.reference_solver, "--reference-solver"));
  study.reference_rtol = app_options.reference_rtol;
  study.jobs = app_options.jobs > 0 ? app_options.jobs : studies::default_jobs();
  study.progress = true;
  if (!study.schemes.empty()) {
    check_scheme_run(model, study.h0 / std::ldexp(1.0, study.levels - 1), times, app_options.limits,
                     "--dt/2^(levels-1) =");
  }
  studies::StudyOutput out(app_options.out_dir);
  study.external = external_methods({app_options.scene,
                                     app_options.external,
                                     {},
                                     app_options.label,
                                     0,
                                     app_options.timeout,
                                     scene_identity(app_options.scene, scene),
                                     app_options.allow_scene_mismatch},
                                    out);
  // --reference-precision (docs/precision.md), as in converge: "auto" repeats the study with a
  // quad reference when the double one leaves runs uncertified and the scene allows it.
  // The schemes against the model before a high-precision reference (quad: minutes).
  studies::check_work_precision_inputs(model, times, study);
  const studies::StudyReferences references(scene, times, app_options.metric,
                                            app_options.reference_solver, "work-precision");
  studies::PolicyOutcome<studies::WorkPrecisionResult> outcome =
      studies::run_work_precision_under_policy(model, times, study, app_options.reference_precision,
                                               app_options.reference_budget, references);
  const studies::WorkPrecisionResult& result = outcome.result;
  const std::string& refused = outcome.refused;

  const std::string table = format_work_precision_table(result);
  // The metric's unit and what it is taken from, against this reference.
  const trajectory::ComparisonReport self =
      trajectory::compare_trajectories(result.reference.table, result.reference.table);
  const std::string unit = trajectory::metric_unit(study.metric);
  const std::string terms = trajectory::metric_terms(self, study.metric);
  studies::StudyRecord record = scene_record(app_options.scene, scene);
  record.table("study")
      .set("kind", "work-precision")
      .set("reference_precision", studies::to_string(outcome.precision_used))
      .set("reference_budget", app_options.reference_budget)
      .set("schemes", study.schemes)
      .set("dt", study.h0)
      .set("levels", study.levels)
      .set("solvers", study.solvers)
      .set("tolerances", study.tolerances)
      .set("repeats", study.repeats)
      .set("metric", study.metric)
      .set("metric_unit", unit)
      .set("metric_terms", terms)
      .set("jobs", study.jobs)
      .set("cpu_time", "thread CPU time of the integration only, minimum over repeats")
      .set("target_errors", studies::default_target_errors());
  if (!refused.empty()) record.table("study").set("reference_refused", refused);
  if (!app_options.external.empty()) {
    record.table("study")
        .set("external", app_options.external)
        .set("label", study.external.front().label)
        .set("external_cpu_time",
             "the program's user + system CPU time (wait4), children included");
    for (std::size_t level = 0; level < static_cast<std::size_t>(study.levels); ++level) {
      const std::string file =
          "run_" + study.external.front().label + "_" + std::to_string(level) + ".csv";
      if (std::filesystem::exists(out.staged(file))) out.add(file);
    }
  }
  studies::add_reference(record, result.reference);
  studies::add_versions(record);

  out.write("work_precision.csv", studies::work_precision_csv(result));
  out.write("work_precision.txt", table);
  out.write_with("reference.csv", [&](const std::string& path) {
    trajectory::write_csv(result.reference.table, path);
  });
  const studies::PlotOutcome plot =
      out.plot("plot_work_precision.py", "work_precision.png",
               {out.staged("work_precision.csv"), out.staged("work_precision.png"),
                "work-precision: " + scene.name, study.metric, unit, terms});
  const std::string csv_path = out.final_path("work_precision.csv");
  out.commit(std::move(record));

  std::cout << "work-precision " << scene.name << "\n" << table;
  std::cout << "wrote " << csv_path << ", work_precision.txt, study.toml, reference.csv";
  std::cout << (plot.ok ? ", " + plot.message : "") << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  bool any_ok = false;
  for (const studies::WorkPrecisionRun& run : result.runs) any_ok = any_ok || run.status == "ok";
  if (!any_ok) {
    std::cerr << "flexref: work-precision refused: no run has a certified error (see the status "
                 "column and the notes)\n";
    return kExitRefused;
  }
  return kExitOk;
}

RegisteredCommand register_work_precision_command(CLI::App& app) {
  auto options = std::make_shared<WorkPrecisionOptions>();
  CLI::App* cmd = app.add_subcommand("work-precision", "error against CPU time, cheapest method");
  add_scheme_ladder(cmd, options->scene, options->schemes, options->dt);
  cmd->add_option("--levels", options->levels, "number of steps: dt, dt/2, ..., dt/2^(levels-1)")
      ->check(integer_in(1, 16))
      ->capture_default_str();
  cmd->add_option("--solvers", options->solvers, "comma-separated list")
      ->delimiter(',')
      ->check(CLI::IsMember({"ida", "cvode", "arkode", "odeint"}))
      ->capture_default_str();
  cmd->add_option("--tolerances", options->tolerances, "comma-separated relative tolerances")
      ->delimiter(',')
      ->check(number_in(1e-14, 1e-1))
      ->capture_default_str();
  cmd->add_option("--repeats", options->repeats, "CPU time: minimum over this many runs")
      ->check(integer_in(1, 100))
      ->capture_default_str();
  cmd->add_option("--metric", options->metric, metric_help("error metric"))
      ->check(CLI::IsMember(trajectory::metric_names()))
      ->capture_default_str();
  add_enum_option(cmd, "--reference-solver", options->reference_solver,
                  "auto | ida | cvode | arkode | odeint | exact",
                  {"auto", "ida", "cvode", "arkode", "odeint", "exact"},
                  studies::parse_reference_solver,
                  [](studies::ReferenceSolver v) { return studies::to_string(v); });
  cmd->add_option("--reference-rtol", options->reference_rtol, "reference tolerance")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  cmd->add_option("--jobs", options->jobs,
                  "parallel runs (0: all cores); timings are per-thread CPU time, cleanest "
                  "with --jobs 1")
      ->check(integer_in(0, 1024));
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();
  add_genalpha_options(
      cmd, options->method_options, [options] { return options->schemes; }, "--schemes");
  cmd->add_option("--external", options->external,
                  "another code's integrator: a command with {scene}, {dt}, {output}, run "
                  "per step; its CPU time is the program's own (docs/external.md)");
  cmd->add_option("--label", options->label, "name of the external method in the table");
  cmd->add_option("--timeout", options->timeout, "seconds per external run (0: no limit)")
      ->check(non_negative_number())
      ->capture_default_str();
  add_allow_scene_mismatch(cmd, options->allow_scene_mismatch);
  add_model_option(cmd, options->model);
  add_enum_option(cmd, "--reference-precision", options->reference_precision,
                  "auto (double; quad when double cannot certify every run and the scene "
                  "allows it) | double | extended | quad (docs/precision.md)",
                  {"auto", "double", "extended", "quad"}, studies::parse_reference_precision,
                  [](studies::ReferencePrecision p) { return studies::to_string(p); });
  add_reference_budget(cmd, options->reference_budget);
  add_limits(cmd, options->limits, true);

  return {cmd, [options, cmd] {
            options->dt_given = cmd->count("--dt") > 0;
            return work_precision_command(*options);
          }};
}

}  // namespace flexref::app
