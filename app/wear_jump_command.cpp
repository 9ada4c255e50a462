#include "app/wear_jump_command.hpp"

#include <algorithm>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "app/scene_metadata.hpp"
#include "scene/scene_reader.hpp"
#include "studies/parallel.hpp"
#include "studies/study_output.hpp"
#include "studies/wear_jump.hpp"
#include "studies/wear_output.hpp"

namespace flexref::app {

int wear_jump_command(const WearJumpCommandOptions& options) {
  const scene::Scene scene = scene::read_scene(options.scene, options.model);
  if (scene.model->wear_depth_count() == 0) {
    throw std::invalid_argument("wear-jump: " + options.scene +
                                " has no contact with a wear law (a [[contact]] key wear = "
                                "{...}, docs/wear.md)");
  }
  studies::WearJumpOptions study;
  study.slow.clear();
  for (const std::string& s : options.slow) study.slow.push_back(studies::parse_slow_integrator(s));
  study.jump_counts = options.jumps;
  study.windows = options.windows;
  studies::CycleJumpOptions& base = study.base;
  base.window = options.windows.front();
  base.transient = options.transient;
  base.first_transient = options.first_transient;
  base.until = options.until > 0.0 ? options.until : scene.end_time;
  base.solver = options.solver;
  base.rtol = options.rtol;
  base.formulation = options.model;
  base.output_step = std::min(scene.output_step,
                              *std::min_element(options.windows.begin(), options.windows.end()));
  study.estimate_factor = options.estimate_factor;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  study.progress = true;

  studies::StudyOutput out(options.out_dir);
  std::cerr << "wear-jump: " << study.slow.size() << " slow-time integrators x "
            << study.jump_counts.size() << " jumps x " << study.windows.size()
            << " windows against the fully coupled reference (" << base.solver << ", rtol "
            << base.rtol << ", " << base.until << " s) on " << studies::workers_text(study.jobs)
            << " ...\n";
  const studies::WearJumpResult result = studies::run_wear_jump(scene.spec, study);

  std::vector<double> counts(options.jumps.begin(), options.jumps.end());
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("study")
      .set("kind", "wear-jump")
      .set("slow", options.slow)
      .set("jump_counts", counts)
      .set("windows", options.windows)
      .set("transient", base.transient)
      .set("first_transient", base.first_transient >= 0.0 ? base.first_transient : base.transient)
      .set("until", base.until)
      .set("solver", base.solver)
      .set("rtol", base.rtol)
      .set("estimate_rtol", base.rtol / study.estimate_factor)
      .set("metric", "max_j |h_j - h_ref,j| / max_j h_ref,j of the final worn profile")
      .set("speedup", "reference CPU / multi-scale CPU (same solver and rtol)")
      .set("order", "from the distances between the final profiles of successive ok levels")
      .set("jobs", study.jobs);
  record.table("reference")
      .set("cpu_seconds", result.reference_cpu)
      .set("steps", result.reference_steps)
      .set("estimate", result.reference_estimate)
      .set("max_depth", result.reference_depth.maxCoeff());
  studies::add_versions(record);

  const std::string table = studies::format_wear_jump(result);
  out.write("wear_jump.csv", studies::wear_jump_csv(result));
  out.write("wear_jump.txt", table);
  out.write("wear_jump_distances.csv", studies::wear_jump_distances_csv(result));
  // The worn profile of the level closest to the reference beside the reference's.
  const studies::WearJumpRow* shown = nullptr;
  for (const studies::WearJumpRow& r : result.rows) {
    if (r.depth.size() != result.reference_depth.size()) continue;  // a failed level
    if (shown == nullptr || r.error < shown->error) shown = &r;
  }
  if (shown != nullptr) {
    out.write("wear_profile.csv",
              studies::wear_profile_csv(result.layout, shown->depth, result.reference_depth));
  }
  const std::string title = scene.name + ": multi-scale wear against the fully coupled reference";
  const studies::PlotOutcome plot =
      out.plot("plot_wear.py", "wear_jump.png",
               {"jump", out.staged("wear_jump.csv"), out.staged("wear_jump.png"), title,
                out.staged("wear_jump_distances.csv")});
  studies::PlotOutcome profile_plot{false, ""};
  if (shown != nullptr) {
    const std::string profile_title = scene.name + ": worn profile, " + shown->slow + " with " +
                                      std::to_string(shown->jumps) + " jumps, and the reference";
    profile_plot = out.plot(
        "plot_wear.py", "wear_profile.png",
        {"profile", out.staged("wear_profile.csv"), out.staged("wear_profile.png"), profile_title});
  }
  const std::string csv_path = out.final_path("wear_jump.csv");
  out.commit(std::move(record));

  std::cout << table << "wrote " << csv_path
            << ", wear_jump.txt, wear_jump_distances.csv, study.toml";
  if (plot.ok) std::cout << ", " << plot.message;
  if (profile_plot.ok) std::cout << ", " << profile_plot.message;
  std::cout << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  return kExitOk;
}

RegisteredCommand register_wear_jump_command(CLI::App& app) {
  auto options = std::make_shared<WearJumpCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "wear-jump", "the multi-scale wear scheme against the fully coupled reference");
  cmd->add_option("scene", options->scene, "scene file with a wear law (TOML)")->required();
  cmd->add_option("--slow", options->slow, "slow-time integrators (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember({"euler", "heun", "ab2"}))
      ->capture_default_str();
  cmd->add_option("--jumps", options->jumps, "jumps over the slow time (comma-separated)")
      ->delimiter(',')
      ->check(integer_in(1, 100000))
      ->capture_default_str();
  cmd->add_option("--windows", options->windows, "T_w: s of dynamics averaged (comma-separated)")
      ->delimiter(',')
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--transient", options->transient,
                  "T_tr: s discarded at the start of every window")
      ->check(non_negative_number())
      ->capture_default_str();
  cmd->add_option("--first-transient", options->first_transient,
                  "s discarded at the start of the first window (default: the transient)")
      ->check(non_negative_number());
  cmd->add_option("--until", options->until, "T: s of slow time (default: the scene's end time)")
      ->check(positive_number());
  cmd->add_option("--solver", options->solver,
                  "the reference's and the windows' solver: cvode | ida | arkode | odeint")
      ->check(CLI::IsMember({"cvode", "ida", "arkode", "odeint"}))
      ->capture_default_str();
  cmd->add_option("--rtol", options->rtol, "the reference's and the windows' tolerance")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  add_estimate_factor(cmd, options->estimate_factor);
  add_model_option(cmd, options->model);
  cmd->add_option("--jobs", options->jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024))
      ->capture_default_str();
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();
  return {cmd, [options] { return wear_jump_command(*options); }};
}

}  // namespace flexref::app
