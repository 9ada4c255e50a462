#include "app/wear_command.hpp"

#include <cmath>
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
#include "studies/progress.hpp"
#include "studies/study_output.hpp"
#include "studies/wear_cycle_jump.hpp"
#include "studies/wear_output.hpp"

namespace flexref::app {
namespace {

/// The windows a run takes: one per jump (Euler, AB2), two (Heun), and AB2's first by Heun.
long expected_windows(studies::SlowIntegrator slow, double until, double jump) {
  const auto jumps = static_cast<long>(std::ceil(until / jump - 1e-9));
  if (slow == studies::SlowIntegrator::kHeun) return 2 * jumps;
  return slow == studies::SlowIntegrator::kAb2 ? jumps + 1 : jumps;
}

std::string summary(const studies::CycleJumpResult& r, const std::string& scene) {
  std::ostringstream out;
  out.precision(4);
  const studies::CycleJumpOptions& o = r.options;
  out << "wear: multi-scale scheme on " << scene << " (" << studies::to_string(o.slow)
      << " in slow time)\n";
  out << "  slow time " << o.until << " s in " << r.jumps << " jumps of " << o.jump << " s; "
      << r.windows.size() << " windows of " << o.window << " s averaged after a transient of "
      << o.transient << " s (the first "
      << (o.first_transient >= 0.0 ? o.first_transient : o.transient) << " s)\n";
  out << "  cost: " << r.fast_time << " s of dynamics (" << o.solver << ", rtol " << o.rtol
      << ") for " << o.until << " s of slow time, " << r.cpu_seconds << " s CPU\n";
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const Eigen::VectorXd h = r.path.back().depth.segment(r.channel_first[c], r.channel_count[c]);
    Eigen::Index where = 0;
    const double largest = h.maxCoeff(&where);
    out << "  " << r.channels[c] << ": largest depth " << largest << " m at "
        << (r.channel_sectors[c] > 0 ? "sector " : "point ") << where + 1 << " of " << h.size()
        << "\n";
  }
  for (const std::string& change : r.regime_changes) {
    out << "note: the contact regime changes inside " << change << "\n";
  }
  if (!r.slow_instability.empty()) {
    out << "note: unstable in slow time, " << r.slow_instability << "\n";
  }
  return out.str();
}

}  // namespace

int wear_command(const WearCommandOptions& options) {
  const scene::Scene scene = scene::read_scene(options.scene, options.model);
  studies::CycleJumpOptions o;
  o.window = options.window;
  o.transient = options.transient;
  o.first_transient = options.first_transient;
  o.until = options.until > 0.0 ? options.until : scene.end_time;
  o.jump = options.jump > 0.0 ? options.jump : o.until / 10.0;
  o.slow = studies::parse_slow_integrator(options.slow);
  o.solver = options.solver;
  o.rtol = options.rtol;
  o.formulation = options.model;
  o.output_step = std::min(scene.output_step, o.window);
  if (scene.model->wear_depth_count() == 0) {
    throw std::invalid_argument("wear: " + options.scene +
                                " has no contact with a wear law (a [[contact]] key wear = "
                                "{...}, docs/wear.md)");
  }
  if (o.jump > o.until) {
    throw std::invalid_argument("wear: --jump is longer than the slow time (--until)");
  }

  studies::StudyOutput out(options.out_dir);
  studies::Progress progress("wear", expected_windows(o.slow, o.until, o.jump), "windows");
  o.on_window = [&progress](double) { progress.advance(); };
  const studies::CycleJumpResult result = studies::run_cycle_jump(scene.spec, o);
  progress.finish();

  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("study")
      .set("kind", "wear")
      .set("slow", std::string(studies::to_string(o.slow)))
      .set("window", o.window)
      .set("transient", o.transient)
      .set("first_transient", o.first_transient >= 0.0 ? o.first_transient : o.transient)
      .set("jump", o.jump)
      .set("until", o.until)
      .set("solver", o.solver)
      .set("rtol", o.rtol)
      .set("jumps", result.jumps)
      .set("windows", static_cast<long>(result.windows.size()))
      .set("fast_time", result.fast_time)
      .set("cpu_seconds", result.cpu_seconds);
  studies::add_versions(record);

  const std::string text = summary(result, scene.name);
  out.write("wear_depth.csv", studies::wear_path_csv(result));
  out.write("wear_profile.csv", studies::wear_profile_csv(result, result.path.back().depth));
  out.write("wear_windows.csv", studies::wear_windows_csv(result));
  out.write("wear.txt", text);
  std::ostringstream title;
  title << scene.name << ", " << studies::to_string(o.slow) << ", D = " << o.jump << " s";
  const studies::PlotOutcome depth_plot =
      out.plot("plot_wear.py", "wear_depth.png",
               {"depth", out.staged("wear_depth.csv"), out.staged("wear_depth.png"), title.str()});
  const studies::PlotOutcome profile_plot = out.plot(
      "plot_wear.py", "wear_profile.png",
      {"profile", out.staged("wear_profile.csv"), out.staged("wear_profile.png"), title.str()});
  const std::string csv_path = out.final_path("wear_depth.csv");
  out.commit(std::move(record));

  std::cout << text << "wrote " << csv_path
            << ", wear_profile.csv, wear_windows.csv, wear.txt, study.toml";
  for (const studies::PlotOutcome* p : {&depth_plot, &profile_plot}) {
    if (p->ok) std::cout << ", " << p->message;
  }
  std::cout << "\n";
  for (const studies::PlotOutcome* p : {&depth_plot, &profile_plot}) {
    if (!p->ok) std::cout << p->message << "\n";
  }
  return kExitOk;
}

RegisteredCommand register_wear_command(CLI::App& app) {
  auto options = std::make_shared<WearCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "wear", "multi-scale (cycle-jump) wear: windows of dynamics, jumps of slow time");
  cmd->add_option("scene", options->scene, "scene file with a wear law (TOML)")->required();
  cmd->add_option("--window", options->window, "T_w: s of dynamics averaged per window")
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--transient", options->transient,
                  "T_tr: s discarded at the start of every window")
      ->check(non_negative_number())
      ->capture_default_str();
  cmd->add_option("--first-transient", options->first_transient,
                  "s discarded at the start of the first window (default: the transient)")
      ->check(non_negative_number());
  cmd->add_option("--jump", options->jump, "D: s of slow time per jump (default: until/10)")
      ->check(positive_number());
  cmd->add_option("--until", options->until, "T: s of slow time (default: the scene's end time)")
      ->check(positive_number());
  cmd->add_option("--slow", options->slow, "slow-time integrator: euler | heun | ab2")
      ->check(CLI::IsMember({"euler", "heun", "ab2"}))
      ->capture_default_str();
  cmd->add_option("--solver", options->solver, "the windows' solver: cvode | ida | arkode | odeint")
      ->check(CLI::IsMember({"cvode", "ida", "arkode", "odeint"}))
      ->capture_default_str();
  cmd->add_option("--rtol", options->rtol, "the windows' tolerance")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  add_model_option(cmd, options->model);
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();
  return {cmd, [options] { return wear_command(*options); }};
}

}  // namespace flexref::app
