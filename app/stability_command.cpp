#include "app/stability_command.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "app/input_checks.hpp"
#include "app/scene_metadata.hpp"
#include "lie/stepper.hpp"
#include "scene/scene_reader.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/stability.hpp"
#include "studies/stability_sweeps.hpp"
#include "studies/study_output.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
namespace {

/// `count` values spaced logarithmically in [lo, hi] (just lo when count is 1).
std::vector<double> log_spaced(double lo, double hi, int count) {
  if (!(lo > 0.0) || !(hi >= lo) || count < 1) {
    throw std::invalid_argument("stability: need 0 < --min <= --max and --count >= 1");
  }
  std::vector<double> values;
  for (int i = 0; i < count; ++i) {
    const double f = count == 1 ? 0.0 : static_cast<double>(i) / (count - 1);
    values.push_back(lo * std::pow(hi / lo, f));
  }
  return values;
}

/// Refuses, before any work, a swept value the sweep cannot use, naming the parameter's domain
/// (the studies' own checks would fail later with an internal message).
void check_values(studies::StabilityParameter parameter, const std::vector<double>& values) {
  for (const double v : values) {
    std::ostringstream value;
    value << v;
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw std::invalid_argument(std::string("stability: --parameter ") +
                                  studies::to_string(parameter) + ": the value " + value.str() +
                                  " must be positive and finite");
    }
    if (parameter == studies::StabilityParameter::kInertiaRatio && v < 1.0) {
      throw std::invalid_argument(
          "stability: --parameter inertia_ratio: the value " + value.str() +
          " is below 1; the ratio J3/J1 of the slender rod diag(J1, J1, J3) is at least 1 "
          "(J3 is the largest principal inertia)");
    }
  }
}

/// Refuses step counts beyond --max-steps.
void check_steps(const char* option, long steps, const WorkLimits& limits) {
  if (static_cast<double>(steps) > limits.max_steps) {
    std::ostringstream out;
    out << "stability: " << option << " " << steps << " is beyond the limit of " << limits.max_steps
        << " steps per run: lower it or raise --max-steps";
    throw std::invalid_argument(out.str());
  }
}

/// The modal-frequency and contact-stiffness sweeps (studies/stability_sweeps.hpp).
int linear_stability_command(const StabilityCommandOptions& options) {
  if (!options.scene.empty()) {
    throw std::invalid_argument(std::string("stability: --parameter ") +
                                studies::to_string(options.parameter) +
                                " uses its built-in model (studies/stability_sweeps.hpp); give "
                                "no scene");
  }
  studies::LinearSweepOptions study;
  study.parameter = options.parameter;
  study.schemes = options.schemes;
  study.method_options = options.method_options;
  study.relative_tolerance = options.rtol;
  study.steps = options.steps;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  const bool modal = options.parameter == studies::StabilityParameter::kModalFrequency;
  if (!options.values.empty()) {
    study.values = options.values;
  } else {
    const double lo = options.min > 0.0 ? options.min : (modal ? 10.0 : 1e3);
    const double hi = options.max > 0.0 ? options.max : (modal ? 1e4 : 1e9);
    study.values = log_spaced(lo, hi, options.count);
  }
  check_values(options.parameter, study.values);
  check_steps("--steps", options.steps, options.limits);
  study.progress = true;
  studies::StudyOutput out(options.out_dir);
  std::cerr << "stability: " << study.values.size() * study.schemes.size() << " bisections ("
            << studies::to_string(options.parameter) << ") on " << studies::workers_text(study.jobs)
            << " ...\n";
  const std::vector<studies::LinearSweepPoint> points = studies::run_linear_sweep(study);

  const std::string model =
      modal ? "flexible_spinner's hub and beam (LTE, torque-free, spin 1 rad/s, modes deflected), "
              "EI scaled to put omega_max at the swept value"
            : "ball m = 1 kg on a linear undamped penalty floor under gravity, oscillating "
              "about its static penetration";
  const std::string table =
      "model: " + model + "\n" + studies::format_linear_sweep_table(options.parameter, points);
  studies::StudyRecord record;
  record.table("study")
      .set("kind", "stability")
      .set("parameter", studies::to_string(options.parameter))
      .set("model", model)
      .set("values", study.values)
      .set("schemes", study.schemes)
      .set("steps_per_run", study.steps)
      .set("growth_factor", study.growth_factor)
      .set("relative_tolerance", study.relative_tolerance)
      .set("jobs", study.jobs);
  studies::add_versions(record);
  out.write("stability.csv", studies::linear_sweep_csv(options.parameter, points));
  out.write("stability.txt", table);
  const studies::PlotOutcome plot =
      out.plot("plot_stability.py", "stability.png",
               {"linear", out.staged("stability.csv"), out.staged("stability.png"),
                std::string("stability: ") + studies::to_string(options.parameter)});
  const std::string csv_path = out.final_path("stability.csv");
  out.commit(std::move(record));
  std::cout << "stability\n"
            << table << "wrote " << csv_path << ", stability.txt, study.toml"
            << (plot.ok ? ", " : "\n") << plot.message << "\n";
  return kExitOk;
}

}  // namespace

int stability_command(const StabilityCommandOptions& options) {
  if (studies::is_linear_sweep(options.parameter)) {
    return linear_stability_command(options);
  }
  studies::StabilityOptions study;
  study.parameter = options.parameter;
  study.schemes = options.schemes;
  study.method_options = options.method_options;
  std::string body_source = "built-in free_spin body, J = diag(3, 4, 5), W0 = (0.2, 0.3, 2.0)";
  studies::StudyRecord record;
  record.table("scene").set("file", "").set("name", "built-in free_spin body");
  if (!options.scene.empty()) {
    const scene::Scene scene = load_scene(options.scene);
    int free_body = -1;
    for (int i = 0; i < scene.model->num_bodies() && free_body < 0; ++i) {
      if (scene.model->body(i).is_free() && !scene.model->body(i).is_flexible()) free_body = i;
    }
    if (free_body < 0) {
      throw std::invalid_argument("stability: scene '" + options.scene +
                                  "' has no free rigid body");
    }
    const core::RigidBodyDescription& body = scene.model->body(free_body).description();
    if (!(body.initial.w_WB_B.norm() > 0.0)) {
      throw std::invalid_argument("stability: body '" + body.name + "' of scene '" + options.scene +
                                  "' has no initial angular velocity");
    }
    study.I_Bcm_B = body.I_Bcm_B;
    study.w_direction_B = body.initial.w_WB_B;
    body_source = "inertia and W0 of body '" + body.name + "' of " + options.scene +
                  " (torque-free: the scene's loads are not used)";
    record = scene_record(options.scene, scene);
  }
  const bool spin_sweep = options.parameter == studies::StabilityParameter::kSpin;
  if (!options.values.empty()) {
    study.values = options.values;
  } else {
    const double lo = options.min > 0.0 ? options.min : (spin_sweep ? 0.1 : 1.0);
    const double hi = options.max > 0.0 ? options.max : (spin_sweep ? 1000.0 : 1e6);
    study.values = log_spaced(lo, hi, options.count);
  }
  check_values(options.parameter, study.values);
  check_steps("--steps", options.steps, options.limits);
  check_steps("--long-run-steps", options.long_run_steps, options.limits);
  study.spin = options.spin > 0.0 ? options.spin : study.w_direction_B.norm();
  study.criterion.steps = options.steps;
  study.criterion.energy_factor = options.energy_factor;
  study.criterion.momentum_factor = options.energy_factor;
  study.relative_tolerance = options.rtol;
  study.degenerate = options.degenerate;
  study.long_run_steps = options.long_run_steps;
  study.long_run_h = options.long_run_dt;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  study.progress = true;

  studies::StudyOutput out(options.out_dir);
  std::cerr << "stability: " << study.values.size() * study.schemes.size() << " bisections"
            << (study.degenerate ? " + degenerate set" : "")
            << (study.long_run_steps > 0
                    ? " + long runs of " + std::to_string(study.long_run_steps) + " steps"
                    : "")
            << " on " << studies::workers_text(study.jobs) << " ...\n";
  const studies::StabilityResult result = studies::run_stability(study);

  const std::string table = "body: " + body_source + "\n" + studies::format_stability_table(result);
  record.table("study")
      .set("kind", "stability")
      .set("parameter", studies::to_string(study.parameter))
      .set("values", study.values)
      .set("schemes", study.schemes)
      .set("inertia_B",
           std::vector<double>{study.I_Bcm_B(0, 0), study.I_Bcm_B(1, 1), study.I_Bcm_B(2, 2)})
      .set("w_direction_B", std::vector<double>{study.w_direction_B(0), study.w_direction_B(1),
                                                study.w_direction_B(2)})
      .set("spin", study.spin)
      .set("steps_per_run", study.criterion.steps)
      .set("energy_factor", study.criterion.energy_factor)
      .set("momentum_factor", study.criterion.momentum_factor)
      .set("relative_tolerance", study.relative_tolerance)
      .set("degenerate", study.degenerate)
      .set("long_run_steps", study.long_run_steps)
      .set("long_run_dt", study.long_run_h)
      .set("jobs", study.jobs);
  studies::add_versions(record);

  out.write("stability.csv", studies::stability_csv(result));
  out.write("stability.txt", table);
  const studies::PlotOutcome plot =
      out.plot("plot_stability.py", "stability.png",
               {"sweep", out.staged("stability.csv"), out.staged("stability.png"),
                std::string("stability: ") + studies::to_string(study.parameter)});
  std::vector<std::string> written{out.final_path("stability.csv"), "stability.txt", "study.toml"};
  std::vector<std::string> plot_problems;
  (plot.ok ? written : plot_problems).push_back(plot.message);
  if (!result.long_run.empty()) {
    out.write("long_run.csv", studies::long_run_csv(result));
    written.push_back("long_run.csv");
    const studies::PlotOutcome long_plot =
        out.plot("plot_stability.py", "long_run.png",
                 {"long_run", out.staged("long_run.csv"), out.staged("long_run.png"), "long run"});
    (long_plot.ok ? written : plot_problems).push_back(long_plot.message);
  }
  out.commit(std::move(record));

  std::cout << "stability\n" << table << "wrote ";
  for (std::size_t i = 0; i < written.size(); ++i) std::cout << (i ? ", " : "") << written[i];
  std::cout << "\n";
  for (const std::string& problem : plot_problems) std::cout << problem << "\n";
  return kExitOk;
}

RegisteredCommand register_stability_command(CLI::App& app) {
  auto options = std::make_shared<StabilityCommandOptions>();
  CLI::App* cmd =
      app.add_subcommand("stability",
                         "largest stable step vs spin rate, inertia ratio, modal frequency or "
                         "contact stiffness");
  cmd->add_option("scene", options->scene,
                  "optional scene: first free body's inertia and W0 direction");
  add_enum_option(cmd, "--parameter", options->parameter,
                  "spin | inertia_ratio | modal_frequency | contact_stiffness",
                  {"spin", "inertia_ratio", "modal_frequency", "contact_stiffness"},
                  studies::parse_stability_parameter,
                  [](studies::StabilityParameter p) { return studies::to_string(p); });
  auto* values_opt =
      cmd->add_option("--values", options->values,
                      "swept values (comma-separated): spin rad/s > 0, inertia_ratio J3/J1 >= 1, "
                      "modal_frequency rad/s > 0, contact_stiffness N/m > 0")
          ->delimiter(',')
          ->check(positive_number());
  cmd->add_option("--min", options->min,
                  "log-spaced range start (default: spin 0.1, inertia_ratio 1, modal_frequency "
                  "10, contact_stiffness 1e3)")
      ->check(positive_number())
      ->excludes(values_opt);
  cmd->add_option("--max", options->max,
                  "log-spaced range end (default: spin 1000, inertia_ratio 1e6, "
                  "modal_frequency 1e4, contact_stiffness 1e9)")
      ->check(positive_number())
      ->excludes(values_opt);
  cmd->add_option("--count", options->count, "number of values")
      ->check(integer_in(1, 200))
      ->capture_default_str();
  cmd->add_option("--schemes", options->schemes, "comma-separated list")
      ->delimiter(',')
      ->check(CLI::IsMember(lie::scheme_names()))
      ->capture_default_str();
  cmd->add_option("--spin", options->spin,
                  "|W0| for the ratio sweep and degenerate set (0: the body's) [rad/s]")
      ->check(non_negative_number());
  cmd->add_option("--steps", options->steps, "steps per stability run")
      ->check(integer_in(10L, 100000000L))
      ->capture_default_str();
  cmd->add_option("--energy-factor", options->energy_factor,
                  "unstable when |dE| > f|E0| (and |dpi| > f|pi0|)")
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--rtol", options->rtol, "bisection relative tolerance")
      ->check(number_in(1e-8, 0.5))
      ->capture_default_str();
  cmd->add_flag("--degenerate,!--no-degenerate", options->degenerate,
                "run the degenerate-body set");
  cmd->add_option("--long-run-steps", options->long_run_steps, "0: no long run")
      ->check(integer_in(0, 1000000000000L))
      ->capture_default_str();
  cmd->add_option("--long-run-dt", options->long_run_dt, "long-run step [s]")
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--jobs", options->jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();
  add_genalpha_options(
      cmd, options->method_options, [options] { return options->schemes; }, "--schemes");
  add_limits(cmd, options->limits, true);

  return {cmd, [options] { return stability_command(*options); }};
}

}  // namespace flexref::app
