#include "app/lte_map_command.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "app/input_checks.hpp"
#include "app/scene_metadata.hpp"
#include "scene/scene_reader.hpp"
#include "studies/lte_map.hpp"
#include "studies/lte_map_report.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/study_output.hpp"
#include "trajectory/accuracy_check.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
namespace {

std::string number(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

std::vector<double> ratios(const std::vector<double>& given, double lo, double hi, int count,
                           const std::string& option) {
  if (!given.empty()) {
    for (const double v : given) {
      if (!(v > 0.0) || !std::isfinite(v)) {
        throw std::invalid_argument("lte-map: --" + option + "-ratios must be positive, got " +
                                    number(v));
      }
    }
    return given;
  }
  try {
    return studies::log_spaced_values(lo, hi, count);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("lte-map: --" + option + "-min/max/count: " + e.what());
  }
}

}  // namespace

int lte_map_command(const LteMapCommandOptions& options) {
  const scene::Scene scene = load_scene(options.scene);
  studies::LteMapOptions study;
  study.spin_ratios =
      ratios(options.spin_ratios, options.spin_min, options.spin_max, options.spin_count, "spin");
  study.inertia_ratios = ratios(options.inertia_ratios, options.inertia_min, options.inertia_max,
                                options.inertia_count, "inertia");
  study.end_time = options.end_time > 0.0 ? options.end_time : scene.end_time;
  study.output_step = std::min(scene.output_step, study.end_time);
  limited_output_times(study.end_time, study.output_step, options.limits);
  check_scene_extremes(scene, study.end_time);
  study.solver = studies::to_string(reference_solver_for(*scene.model, options.solver, "--solver"));
  study.rtol = options.rtol;
  study.estimate_factor = options.estimate_factor;
  study.scale_loads = options.scale_loads;
  study.point = options.point;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  study.progress = true;
  // Validate the scene (and find the body) before starting the grid.
  const studies::LteMapBase base = studies::lte_map_base(*scene.model, study);
  study.body = scene.model->body_index(base.body);
  const bool can_stiffen = studies::lte_map_can_stiffen(scene.spec, study.body);
  if (options.truth == LteMapTruth::kStiffened && !can_stiffen) {
    throw std::invalid_argument(
        "lte-map: --truth stiffened: body '" + base.body +
        "' has no geometric-stiffness data (a clamped-free [body.beam], or a modal-data file "
        "with [geometric_stiffness]; docs/geometric_stiffening.md); use --truth coupled");
  }
  study.stiffened_truth = options.truth == LteMapTruth::kStiffened ||
                          (options.truth == LteMapTruth::kAuto && can_stiffen);
  const studies::LteModelFactory factory = studies::lte_map_factory(scene.spec, study.body);

  studies::StudyOutput out(options.out_dir);
  std::cerr << "lte-map: " << study.spin_ratios.size() * study.inertia_ratios.size()
            << " grid points x " << (study.stiffened_truth ? 6 : 4) << " reference runs ("
            << study.solver << ", rtol " << study.rtol << ", " << study.end_time << " s) on "
            << studies::workers_text(study.jobs) << " ...\n";
  const studies::LteMapResult result = studies::run_lte_map(factory, study);

  const std::string table = studies::format_lte_map_table(result);
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("study")
      .set("kind", "lte-map")
      .set("body", base.body)
      .set("point", base.point)
      .set("spin_ratios", study.spin_ratios)
      .set("inertia_ratios", study.inertia_ratios)
      .set("omega1", base.omega1)
      .set("omega1_meaning", "rad/s, first clamped frequency")
      .set("scene_spin", base.spin)
      .set("scene_spin_ratio", base.spin_ratio)
      .set("scene_inertia_ratio", base.inertia_ratio)
      .set("spin_axis_B", std::vector<double>{base.axis_B(0), base.axis_B(1), base.axis_B(2)})
      .set("scale", std::string("hub mass and inertia by hub_scale; initial spin to x*omega1") +
                        (study.scale_loads ? "; [[load]] values by load_scale" : ""))
      .set("scale_loads", study.scale_loads)
      .set("truth", study.stiffened_truth ? "coupled with geometric stiffening"
                                          : "classical coupled (no geometric stiffening)")
      .set("metric",
           "tip_error: max_t |d_m - d_truth| / max_t |d_truth| over [0, end_time]; "
           "envelope_error: max_t |d_m| / max_t |d_truth| - 1; frequency_shift: f_m / f_truth "
           "- 1 (zero crossings over [end_time/2, end_time]); d = elastic deflection of the "
           "point, body frame")
      .set("solver", study.solver)
      .set("rtol", study.rtol)
      .set("estimate_rtol", trajectory::accuracy_check_rtol(study.rtol, study.estimate_factor))
      .set("end_time", study.end_time)
      .set("output_step", study.output_step)
      .set("jobs", study.jobs);
  studies::add_versions(record);

  out.write("lte_map.csv", studies::lte_map_csv(result));
  out.write("lte_map.txt", table);
  const studies::PlotOutcome plot = out.plot(
      "plot_lte_map.py", "lte_map.png",
      {out.staged("lte_map.csv"), out.staged("lte_map.png"),
       "flexref lte-map on " + scene.name + " (" + number(study.end_time) + " s horizon; truth: " +
           (study.stiffened_truth ? "stiffened coupled" : "classical coupled") + ")",
       number(base.spin_ratio), number(base.inertia_ratio)});
  const std::string csv_path = out.final_path("lte_map.csv");
  out.commit(std::move(record));

  std::cout << "lte-map\n" << table << "wrote " << csv_path << ", lte_map.txt, study.toml";
  if (plot.ok) std::cout << ", " << plot.message;
  std::cout << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  // A point without a frequency shift still measured its other metrics.
  bool any_ok = false;
  for (const studies::LteMapPoint& p : result.points) {
    any_ok = any_ok || !p.status.starts_with("failed");
  }
  if (!any_ok) {
    std::cerr << "flexref: lte-map refused: every grid point failed (see the status column)\n";
    return kExitRefused;
  }
  return kExitOk;
}

LteMapTruth parse_lte_map_truth(std::string_view name) {
  if (name == "auto") return LteMapTruth::kAuto;
  if (name == "stiffened") return LteMapTruth::kStiffened;
  if (name == "coupled") return LteMapTruth::kCoupled;
  throw std::invalid_argument("--truth '" + std::string(name) +
                              "': expected auto, stiffened or coupled");
}

const char* to_string(LteMapTruth truth) {
  switch (truth) {
    case LteMapTruth::kAuto:
      return "auto";
    case LteMapTruth::kStiffened:
      return "stiffened";
    case LteMapTruth::kCoupled:
      return "coupled";
  }
  return "auto";
}

RegisteredCommand register_lte_map_command(CLI::App& app) {
  auto options = std::make_shared<LteMapCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "lte-map", "LTE model error vs coupled model over spin ratio and inertia ratio");
  cmd->add_option("scene", options->scene, "scene file with a free flexible body (TOML)")
      ->required();
  auto* lte_spins = cmd->add_option("--spin-ratios", options->spin_ratios,
                                    "Omega0/omega1 values (comma-separated)")
                        ->delimiter(',')
                        ->check(positive_number());
  cmd->add_option("--spin-min", options->spin_min, "log-spaced spin ratios: first")
      ->check(positive_number())
      ->excludes(lte_spins)
      ->capture_default_str();
  cmd->add_option("--spin-max", options->spin_max, "log-spaced spin ratios: last")
      ->check(positive_number())
      ->excludes(lte_spins)
      ->capture_default_str();
  cmd->add_option("--spin-count", options->spin_count, "log-spaced spin ratios: count")
      ->excludes(lte_spins)
      ->check(integer_in(1, 200))
      ->capture_default_str();
  auto* lte_inertias = cmd->add_option("--inertia-ratios", options->inertia_ratios,
                                       "I_flex/I_rigid values (comma-separated)")
                           ->delimiter(',')
                           ->check(positive_number());
  cmd->add_option("--inertia-min", options->inertia_min, "log-spaced inertia ratios: first")
      ->check(positive_number())
      ->excludes(lte_inertias)
      ->capture_default_str();
  cmd->add_option("--inertia-max", options->inertia_max, "log-spaced inertia ratios: last")
      ->check(positive_number())
      ->excludes(lte_inertias)
      ->capture_default_str();
  cmd->add_option("--inertia-count", options->inertia_count, "log-spaced inertia ratios: count")
      ->excludes(lte_inertias)
      ->check(integer_in(1, 200))
      ->capture_default_str();
  add_enum_option(cmd, "--solver", options->solver, "reference solver: cvode | ida | odeint",
                  {"cvode", "ida", "odeint"}, studies::parse_reference_solver,
                  [](studies::ReferenceSolver v) { return studies::to_string(v); });
  cmd->add_option("--rtol", options->rtol, "reference tolerance (both models)")
      ->check(number_in(1e-14, 1e-4))
      ->capture_default_str();
  add_estimate_factor(cmd, options->estimate_factor);
  cmd->add_flag("!--no-scale-loads", options->scale_loads,
                "keep the loads (default: scale them with spin and inertia)");
  add_enum_option(cmd, "--truth", options->truth,
                  "the truth: stiffened (coupled with geometric stiffening) | coupled (the "
                  "classical coupled model) | auto (stiffened when the body can be)",
                  {"auto", "stiffened", "coupled"}, parse_lte_map_truth,
                  [](LteMapTruth t) { return to_string(t); });
  cmd->add_option("--point", options->point, "tracked node point (default: farthest node)");
  cmd->add_option("--end-time", options->end_time, "s (default: the scene's)")
      ->check(positive_number());
  cmd->add_option("--jobs", options->jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();
  add_limits(cmd, options->limits, false);

  return {cmd, [options] { return lte_map_command(*options); }};
}

}  // namespace flexref::app
