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
#include "app/commands.hpp"
#include "app/step_advice.hpp"
#include "core/error.hpp"
#include "core/invariants.hpp"
#include "core/output_times.hpp"
#include "core/step_limit.hpp"
#include "lie/rotational_stability.hpp"
#include "lie/run_scheme.hpp"
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

}  // namespace

int run_command(const RunOptions& options) {
  const scene::Scene scene = load_scene(options.scene, options.model);
  const core::Model& model = *scene.model;
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);
  const long steps = check_scheme_run(model, options.dt, times, options.limits, "--dt");
  check_output_file(options.output, true);
  auto stepper = lie::make_stepper(options.scheme, model);
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
  core::Trajectory trajectory;
  try {
    studies::Progress progress("run: " + options.scheme, steps, "steps");
    trajectory = lie::run_scheme(model, *stepper, options.dt, times, &progress.counter());
  } catch (const core::SolverError& e) {
    throw core::SolverError(
        e.solver(), e.time(), e.step(),
        e.why() + step_advice(model, options.scheme, options.dt, times, spin0.w));
  }
  const double cpu = studies::thread_cpu_seconds() - start;
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
  // The scene's invariants (core/invariants.hpp): a run that breaks them is unstable and is
  // refused like a failed one (exit 3), nothing written.
  const core::InvariantCheck invariants = core::check_invariants(model, trajectory);
  if (const std::optional<core::InvariantBreach>& breach = invariants.breach) {
    // The step to suggest from the spin before the breach (a run-away inflates the spin).
    double spin_before = spin0.w;
    for (std::size_t k = 0; k < trajectory.states.size() && times[k] <= breach->t0; ++k) {
      spin_before = std::max(spin_before, lie::largest_spin(model, trajectory.states[k]).w);
    }
    throw core::SolverError(options.scheme, breach->t,
                            std::lround((breach->t - times[0]) / options.dt),
                            "the run is unstable: " + breach->describe() +
                                step_advice(model, options.scheme, options.dt, times, spin_before));
  }
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
  auto genalpha = std::make_shared<GenalphaCliOptions>();
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
      cmd, *genalpha, [options] { return std::vector<std::string>{options->scheme}; }, "--scheme");

  return {cmd, [options, genalpha] {
            genalpha->apply();
            return run_command(*options);
          }};
}

}  // namespace flexref::app
