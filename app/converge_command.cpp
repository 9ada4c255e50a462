#include "app/converge_command.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <utility>

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
#include "studies/convergence.hpp"
#include "studies/high_precision_references.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/reference_policy.hpp"
#include "studies/reference_record.hpp"
#include "studies/study_output.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {

int converge_command(const ConvergeOptions& options) {
  const scene::Scene scene = load_scene(options.scene, options.model);
  const core::Model& model = *scene.model;
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);

  studies::ConvergenceOptions study;
  const bool external = !options.external.empty() || !options.runs.empty();
  // Beside an external method the built-in schemes run only when asked for.
  study.schemes = external && !options.schemes_given ? std::vector<std::string>{} : options.schemes;
  study.method_options = options.method_options;
  study.h0 = coarsest_step(options.dt, options.dt_given, scene.output_step);
  study.levels = options.levels;
  study.metric = options.metric;
  study.reference_solver = studies::to_string(
      reference_solver_for(model, options.reference_solver, "--reference-solver"));
  study.reference_rtol = options.reference_rtol;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  study.progress = true;
  // Every refusal before any work: the schemes on this model, each level's grid, the finest
  // level's step count, the output folder.
  studies::check_convergence_inputs(model, times, study);
  // --dt and --levels set the steps of the schemes and of an --external program; runs made
  // earlier (--runs alone) have their own steps and are read under the contract.
  if (!study.schemes.empty() || !options.external.empty()) {
    check_scheme_run(model, study.h0 / std::ldexp(1.0, study.levels - 1), times, options.limits,
                     "--dt/2^(levels-1) =");
  }
  studies::StudyOutput out(options.out_dir);
  study.external = external_methods(
      {options.scene, options.external, options.runs, options.label, options.claimed_order,
       options.timeout, scene_identity(options.scene, scene), options.allow_scene_mismatch},
      out);
  // --reference-precision (docs/precision.md): a given precision, or "auto": the double
  // reference, and when it cannot certify every level and the scene is one the extended/quad
  // model carries, the study again with a quad reference.
  const studies::StudyReferences references(scene, times, options.metric, options.reference_solver,
                                            "converge");
  studies::PolicyOutcome<studies::ConvergenceResult> outcome =
      studies::run_convergence_under_policy(model, times, study, options.reference_precision,
                                            options.reference_budget, references);
  const studies::ConvergenceResult& result = outcome.result;
  const std::string& refused = outcome.refused;
  for (const auto& method : study.external) {
    if (options.external.empty()) break;
    for (std::size_t level = 0; level < result.levels.size(); ++level) {
      const std::string file = "run_" + method.label + "_" + std::to_string(level) + ".csv";
      if (std::filesystem::exists(out.staged(file))) out.add(file);
    }
  }

  const std::string table = format_convergence_table(result);
  // The metric's unit and what it is taken from, against this reference.
  const trajectory::ComparisonReport self =
      trajectory::compare_trajectories(result.reference.table, result.reference.table);
  const std::string unit = trajectory::metric_unit(study.metric);
  const std::string terms = trajectory::metric_terms(self, study.metric);
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("study")
      .set("kind", "converge")
      .set("schemes", study.schemes)
      .set("dt", study.h0)
      .set("levels", options.levels)
      .set("reference_precision", studies::to_string(outcome.precision_used))
      .set("reference_budget", options.reference_budget)
      .set("metric", options.metric)
      .set("metric_unit", unit)
      .set("metric_terms", terms)
      .set("jobs", study.jobs)
      .set("explicit_step_limit", result.step_limit.h)
      .set("explicit_step_limit_of", result.step_limit.what);
  if (!refused.empty()) record.table("study").set("reference_refused", refused);
  if (!options.external.empty()) record.table("study").set("external", options.external);
  if (!options.runs.empty()) record.table("study").set("runs", options.runs);
  if (external) record.table("study").set("label", study.external.front().label);
  studies::add_reference(record, result.reference);
  studies::add_versions(record);

  out.write("convergence.csv", studies::convergence_csv(result));
  out.write("convergence.txt", table);
  out.write_with("reference.csv", [&](const std::string& path) {
    trajectory::write_csv(result.reference.table, path);
  });
  std::ostringstream limit;
  limit.precision(17);
  limit << result.step_limit.h;
  // The fitted orders for the legend: "c1=2.0012,c2=no order (2 valid levels),...".
  std::ostringstream orders;
  for (const studies::SchemeSummary& summary : result.summaries) {
    orders << (orders.tellp() > 0 ? "," : "") << summary.scheme << '=';
    if (summary.refused()) {
      orders << "no order: " << summary.fitted_levels << " valid level"
             << (summary.fitted_levels == 1 ? "" : "s");
    } else {
      orders << summary.fitted_order;
    }
  }
  const studies::PlotOutcome plot = out.plot(
      "plot_convergence.py", "convergence.png",
      {out.staged("convergence.csv"), out.staged("convergence.png"), "convergence: " + scene.name,
       limit.str(), result.step_limit.what, orders.str(), study.metric, unit, terms});
  const std::string csv_path = out.final_path("convergence.csv");
  out.commit(std::move(record));

  std::cout << "converge " << scene.name << "\n" << table;
  std::cout << "wrote " << csv_path << ", convergence.txt, study.toml, reference.csv";
  std::cout << (plot.ok ? ", " + plot.message : "") << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  if (result.refused()) {
    std::cerr << "flexref: converge refused: a scheme has fewer than "
              << studies::SchemeSummary::kMinFittedLevels
              << " valid levels, so no order is reported for it (see the notes above)\n";
    return kExitRefused;
  }
  return kExitOk;
}

RegisteredCommand register_converge_command(CLI::App& app) {
  auto options = std::make_shared<ConvergeOptions>();
  CLI::App* cmd = app.add_subcommand("converge", "observed orders of convergence");
  add_scheme_ladder(cmd, options->scene, options->schemes, options->dt);
  cmd->add_option("--levels", options->levels,
                  "number of levels: steps dt, dt/2, ..., dt/2^(levels-1); an order is fitted "
                  "from at least 3 valid levels")
      ->check(integer_in(3, 16))
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
  cmd->add_option("--jobs", options->jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();
  add_genalpha_options(
      cmd, options->method_options, [options] { return options->schemes; }, "--schemes");
  add_model_option(cmd, options->model);
  add_enum_option(cmd, "--reference-precision", options->reference_precision,
                  "auto (double; quad when double cannot certify every level and the scene "
                  "allows it) | double | extended | quad (docs/precision.md)",
                  {"auto", "double", "extended", "quad"}, studies::parse_reference_precision,
                  [](studies::ReferencePrecision p) { return studies::to_string(p); });
  add_reference_budget(cmd, options->reference_budget);
  add_limits(cmd, options->limits, true);
  auto* conv_external =
      cmd->add_option("--external", options->external,
                      "another code's integrator: a command with {scene}, {dt}, {output}, "
                      "run once per level (docs/external.md)");
  cmd->add_option("--runs", options->runs, "runs already made, as DT=FILE pairs (docs/external.md)")
      ->excludes(conv_external);
  cmd->add_option("--label", options->label, "name of the external method in the table");
  cmd->add_option("--order", options->claimed_order, "the external method's claimed order")
      ->check(integer_in(1, 20));
  cmd->add_option("--timeout", options->timeout, "seconds per external run (0: no limit)")
      ->check(non_negative_number())
      ->capture_default_str();
  add_allow_scene_mismatch(cmd, options->allow_scene_mismatch);

  return {cmd, [options, cmd] {
            options->schemes_given = cmd->count("--schemes") > 0;
            options->dt_given = cmd->count("--dt") > 0;
            return converge_command(*options);
          }};
}

}  // namespace flexref::app
