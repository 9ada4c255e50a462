#include <cmath>
#include <ctime>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "core/output_times.hpp"
#include "core/step_limit.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "scene/scene_reader.hpp"
#include "studies/parallel.hpp"
#include "studies/progress.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::app {

int run_command(const RunOptions& options) {
  const scene::Scene scene = load_scene(options.scene, parse_formulation(options.model));
  const core::Model& model = *scene.model;
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);
  const long steps = check_scheme_run(model, options.dt, times, options.limits, "--dt");
  check_output_file(options.output, true);
  auto stepper = lie::make_stepper(options.scheme, model);
  // Central differences are stable for h ω ≤ 2 on every elastic mode and penalty element
  // (core/step_limit.hpp): warn when the step exceeds one (implicit schemes stay stable but do
  // not resolve the mode).
  for (const core::PenaltyMode& m : core::stiff_modes(model)) {
    if (options.dt <= m.step_limit) continue;
    const bool flexible = m.kind == "flexible body";
    std::cerr << "flexref: warning: step " << options.dt << " s exceeds 2/omega"
              << (flexible ? "_max" : "") << " = " << m.step_limit << " s of "
              << (flexible ? "flexible body " : "") << m.label << " (omega"
              << (flexible ? "_max" : "") << " = " << m.frequency
              << " rad/s): explicit central differences would be unstable and "
              << (flexible ? "the highest modes are" : "the " + m.kind + " is")
              << " not resolved\n";
  }
  const double start = studies::thread_cpu_seconds();
  core::Trajectory trajectory;
  {
    studies::Progress progress("run: " + options.scheme, steps, "steps");
    trajectory = lie::run_scheme(model, *stepper, options.dt, times, &progress.counter());
  }
  const double cpu = studies::thread_cpu_seconds() - start;
  const studies::TrajectoryTable table = studies::tabulate(model, trajectory);
  studies::write_csv(table, options.output);

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
      .set("units", studies::trajectory_units(model));
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

}  // namespace flexref::app
