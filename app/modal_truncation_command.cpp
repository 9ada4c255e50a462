#include "app/modal_truncation_command.hpp"

#include <algorithm>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "app/scene_metadata.hpp"
#include "scene/scene_reader.hpp"
#include "studies/modal_truncation.hpp"
#include "studies/parallel.hpp"
#include "studies/study_output.hpp"
#include "trajectory/accuracy_check.hpp"

namespace flexref::app {

int modal_truncation_command(const ModalTruncationCommandOptions& options) {
  const core::FlexibleFormulation formulation = options.model;
  const scene::Scene scene = scene::read_scene(options.scene, formulation);
  studies::ModalTruncationOptions study;
  study.mode_counts = options.modes;
  study.end_time = options.end_time > 0.0 ? options.end_time : scene.end_time;
  study.output_step = std::min(scene.output_step, study.end_time);
  study.solver = studies::to_string(reference_solver_for(*scene.model, options.solver, "--solver"));
  study.rtol = options.rtol;
  study.estimate_factor = options.estimate_factor;
  study.formulation = formulation;
  if (!options.body.empty()) {
    study.body = scene.model->body_index(options.body);
    if (study.body < 0) {
      throw std::invalid_argument("modes: --body " + options.body + ": no such body in " +
                                  options.scene);
    }
  }
  study.point = options.point;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  study.progress = true;

  studies::StudyOutput out(options.out_dir);
  std::cerr << "modes: " << study.mode_counts.size() << " mode counts x 2 reference runs ("
            << study.solver << ", rtol " << study.rtol << ", " << study.end_time << " s) on "
            << studies::workers_text(study.jobs) << " ...\n";
  const studies::ModalTruncationResult result = studies::run_modal_truncation(scene.spec, study);

  std::vector<double> counts;
  for (const int m : result.options.mode_counts) counts.push_back(m);
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("study")
      .set("kind", "modes")
      .set("body", result.body)
      .set("point", result.point)
      .set("mode_counts", counts)
      .set("reference_modes", result.reference_modes)
      .set("truncation",
           "beam bodies: the m lowest modes of the same finite-element model; modal-data files: "
           "the file's first m modes")
      .set("metric",
           "max_t |d_m - d_ref| / max_t |d_ref| (d = elastic deflection of the point, body "
           "frame) and max_t geodesic angle between the body attitudes")
      .set("solver", study.solver)
      .set("rtol", study.rtol)
      .set("estimate_rtol", trajectory::accuracy_check_rtol(study.rtol, study.estimate_factor))
      .set("estimate", "difference to a run at estimate_rtol (same output times)")
      .set("end_time", study.end_time)
      .set("output_step", study.output_step)
      .set("jobs", study.jobs);
  studies::add_versions(record);

  const std::string table = studies::format_modal_truncation_table(result);
  out.write("modes.csv", studies::modal_truncation_csv(result));
  out.write("modes.txt", table);
  std::ostringstream title;
  title << "Modal truncation on " << scene.name << " (" << study.end_time << " s, " << result.point
        << ")";
  const studies::PlotOutcome plot =
      out.plot("plot_modal_truncation.py", "modes.png",
               {out.staged("modes.csv"), out.staged("modes.png"), title.str()});
  const std::string csv_path = out.final_path("modes.csv");
  out.commit(std::move(record));

  std::cout << "modes\n" << table << "wrote " << csv_path << ", modes.txt, study.toml";
  if (plot.ok) std::cout << ", " << plot.message;
  std::cout << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  return kExitOk;
}

RegisteredCommand register_modal_truncation_command(CLI::App& app) {
  auto options = std::make_shared<ModalTruncationCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "modes", "reference tip deflection and attitude vs the number of retained modes");
  cmd->add_option("scene", options->scene, "scene file with a flexible body (TOML)")->required();
  cmd->add_option("--modes", options->modes, "mode counts (comma-separated; largest = reference)")
      ->delimiter(',')
      ->check(integer_in(1, 100000))
      ->capture_default_str();
  cmd->add_option("--body", options->body, "flexible body (default: the first)");
  cmd->add_option("--point", options->point, "tracked node point (default: farthest node)");
  add_enum_option(cmd, "--solver", options->solver, "reference solver: odeint | cvode | ida",
                  {"odeint", "cvode", "ida"}, studies::parse_reference_solver,
                  [](studies::ReferenceSolver v) { return studies::to_string(v); });
  cmd->add_option("--rtol", options->rtol, "reference tolerance")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  add_estimate_factor(cmd, options->estimate_factor);
  cmd->add_option("--end-time", options->end_time, "s (default: the scene's)")
      ->check(positive_number());
  add_model_option(cmd, options->model);
  cmd->add_option("--jobs", options->jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();

  return {cmd, [options] { return modal_truncation_command(*options); }};
}

}  // namespace flexref::app
