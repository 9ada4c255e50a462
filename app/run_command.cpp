#include "app/run_command.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <tuple>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "app/input_checks.hpp"
#include "app/output_files.hpp"
#include "app/scene_metadata.hpp"
#include "app/step_advice.hpp"
#include "core/error.hpp"
#include "core/invariants.hpp"
#include "core/joint_check.hpp"
#include "core/output_times.hpp"
#include "core/step_limit.hpp"
#include "lie/rotational_stability.hpp"
#include "lie/run_scheme.hpp"
#include "lie/scheme_support.hpp"
#include "lie/stepper.hpp"
#include "scene/scene_reader.hpp"
#include "studies/parallel.hpp"
#include "studies/progress.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
namespace {

/// The [invariants] table of a run's sidecar: what was monitored from when, the tolerance, and
/// the largest relative change the run reached (core/invariants.hpp).
void add_invariants(studies::StudyRecord& record, const core::InvariantCheck& check, double t0) {
  studies::StudyRecord::Table& table = record.table("invariants");
  table.set("tolerance", core::kInvariantTolerance);
  const core::ModelInvariants& in = check.invariants;
  if (in.energy()) {
    table.set("energy_balance_from", std::max(t0, in.energy_from));
  } else {
    table.set("energy_balance", "not monitored: " + in.energy_reason);
  }
  if (in.momentum()) {
    table.set("momentum_from", std::max(t0, in.momentum_from));
  } else {
    table.set("momentum", "not monitored: " + in.momentum_reason);
  }
  if (in.energy() || in.momentum()) {
    table.set("largest_relative_change", check.worst_relative);
    if (!check.worst_quantity.empty()) table.set("largest_change_of", check.worst_quantity);
  }
}

/// One run of the scheme at dt over the output times, with its checks: the step's own failures,
/// the scene's invariants (core/invariants.hpp) and, with ideal joints, the joints at every output
/// (core/joint_check.hpp: the position rows, which genalpha holds at index 3 to its Newton
/// tolerance, kNewtonTolerance relative to the bodies' positions; its velocity rows drift at the
/// scheme's own order and are reported, not bounded).
RunAttempt attempt_run(const core::Model& model, const std::string& scheme,
                       const lie::MethodOptions& method_options, double dt,
                       const std::vector<double>& times, bool progress_line) {
  RunAttempt a;
  auto stepper = lie::make_stepper(scheme, model, method_options);
  try {
    const long steps = std::lround((times.back() - times.front()) / dt);
    std::optional<studies::Progress> progress;
    if (progress_line) progress.emplace("run: " + scheme, steps, "steps");
    a.trajectory =
        lie::run_scheme(model, *stepper, dt, times, progress ? &progress->counter() : nullptr);
  } catch (const core::SolverError& e) {
    a.solver = e.solver();
    a.time = e.time();
    a.step = e.step();
    a.why = e.why();
    a.spin_until = e.time();
    return a;
  }
  a.invariants = core::check_invariants(model, a.trajectory);
  if (const std::optional<core::InvariantBreach>& breach = a.invariants.breach) {
    a.solver = scheme;
    a.time = breach->t;
    a.step = std::lround((breach->t - times[0]) / dt);
    a.why = "the run is unstable: " + breach->describe();
    a.quantity = breach->quantity;
    a.change = breach->relative();
    a.spin_until = breach->t0;
    return a;
  }
  if (model.has_constraints()) {
    double extent = 0.0;
    for (const core::State& state : a.trajectory.states) {
      for (const core::BodyState& b : state)
        extent = std::max(extent, b.p_WBr.cwiseAbs().maxCoeff());
    }
    // The Newton test measures length rows against the bodies' positions (at least 1 cm).
    const double scale = std::max(1.0, std::max(extent, 1e-2) / model.joint_length_scale());
    const double bound = core::joint_violation_bound(lie::detail::kNewtonTolerance * scale, 0.0,
                                                     model.joint_length_scale());
    if (const std::optional<core::JointBreach> breach =
            core::find_joint_breach(model, a.trajectory, bound, false)) {
      a.solver = scheme;
      a.time = breach->t;
      a.step = std::lround((breach->t - times[0]) / dt);
      a.why = breach->describe();
      a.spin_until = breach->t;
      return a;
    }
  }
  a.passed = true;
  return a;
}

}  // namespace

int run_command(const RunOptions& options) {
  const scene::Scene scene = load_scene(options.scene, options.model);
  const core::Model& model = *scene.model;
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);
  const long steps = check_scheme_run(model, options.dt, times, options.limits, "--dt");
  check_output_file(options.output, true);
  // Central differences are stable for h ω ≤ 2 on every elastic mode and penalty element
  // (core/step_limit.hpp): warn when the step exceeds one, in the scheme's terms.
  for (const core::PenaltyMode& m : core::stiff_modes(model)) {
    const std::string warning = stiff_mode_warning(options.scheme, options.dt, m);
    if (!warning.empty()) std::cerr << "flexref: warning: " << warning << "\n";
  }
  const lie::SpinRate spin0 = lie::largest_spin(model, model.initial_state());
  const std::string spin_warning =
      rotational_step_warning(model, options.scheme, options.dt, model.initial_state(), times[0]);
  if (!spin_warning.empty()) std::cerr << "flexref: warning: " << spin_warning << "\n";
  const double start = studies::thread_cpu_seconds();
  RunAttempt run =
      attempt_run(model, options.scheme, options.method_options, options.dt, times, true);
  const double cpu = studies::thread_cpu_seconds() - start;
  if (!run.passed) {
    // The step to suggest from the spin before the failure (a run-away inflates the spin), run
    // once before it is advised (step_advice.hpp: never a step that cannot help).
    double spin_before = spin0.w;
    for (std::size_t k = 0; k < run.trajectory.states.size() && times[k] <= run.spin_until; ++k) {
      spin_before = std::max(spin_before, lie::largest_spin(model, run.trajectory.states[k]).w);
    }
    const auto retry = [&](double h) {
      std::cerr << "flexref: checking a smaller step: " << options.scheme << " at --dt " << h
                << "\n";
      return attempt_run(model, options.scheme, options.method_options, h, times, false);
    };
    throw core::SolverError(run.solver, run.time, run.step,
                            run.why + verified_step_advice(model, options.scheme, options.dt, times,
                                                           spin_before, run, retry));
  }
  core::Trajectory& trajectory = run.trajectory;
  // The spin the run reached (a pulse spins bodies up): warn when it crossed the limit later.
  lie::SpinRate spin = spin0;
  std::size_t spin_row = 0;
  for (std::size_t k = 0; k < trajectory.states.size(); ++k) {
    const lie::SpinRate s = lie::largest_spin(model, trajectory.states[k]);
    if (s.w > spin.w) std::tie(spin, spin_row) = std::tuple(s, k);
  }
  if (spin_warning.empty()) {
    const std::string late = rotational_step_warning(model, options.scheme, options.dt,
                                                     trajectory.states[spin_row], times[spin_row]);
    if (!late.empty()) std::cerr << "flexref: warning: " << late << "\n";
  }
  const core::InvariantCheck& invariants = run.invariants;
  const trajectory::TrajectoryTable table = trajectory::tabulate(model, trajectory);
  trajectory::write_csv(table, options.output);

  const int energy = table.column("energy");
  const double e_first = table.rows.front()[static_cast<std::size_t>(energy)];
  const double e_last = table.rows.back()[static_cast<std::size_t>(energy)];
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("integrator")
      .set("kind", "scheme")
      .set("scheme", options.scheme)
      .set("dt", options.dt)
      .set("steps", steps)
      .set("cpu_seconds", cpu);
  record.table("columns")
      .set("names", table.columns)
      .set("units", trajectory::trajectory_units(model));
  add_invariants(record, invariants, times[0]);
  studies::add_versions(record);
  write_sidecar(record, options.output);

  summary_stream(options.output) << "run " << scene.name << " with " << options.scheme
                                 << (model.has_flexible_bodies()
                                         ? std::string(" (") +
                                               core::to_string(model.formulation()) + " model)"
                                         : std::string())
                                 << ", dt " << options.dt << " s: " << steps << " steps, " << cpu
                                 << " s CPU; energy " << e_first << " -> " << e_last << " J; wrote "
                                 << options.output << "\n";
  return kExitOk;
}

RegisteredCommand register_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "integrate a scene with a Lie-group scheme");
  cmd->add_option("scene", options->scene, "scene file (TOML)")->required();
  cmd->add_option("--scheme", options->scheme, "c1 | c2 | nmb | genalpha")
      ->check(CLI::IsMember(lie::scheme_names()))
      ->capture_default_str();
  cmd->add_option("--dt", options->dt, "step [s]")->check(positive_number())->capture_default_str();
  cmd->add_option("-o,--output", options->output, std::string("CSV ") + kOutputFileHelp)
      ->required();
  add_model_option(cmd, options->model);
  add_limits(cmd, options->limits, true);
  add_genalpha_options(
      cmd, options->method_options, [options] { return std::vector<std::string>{options->scheme}; },
      "--scheme");

  return {cmd, [options] { return run_command(*options); }};
}

}  // namespace flexref::app
