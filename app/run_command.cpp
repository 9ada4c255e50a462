#include <cmath>
#include <ctime>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "core/output_times.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "scene/scene_reader.hpp"
#include "studies/parallel.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::app {

int run_command(const RunOptions& options) {
  const scene::Scene scene = scene::read_scene(options.scene, parse_formulation(options.model));
  const core::Model& model = *scene.model;
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);
  // Central differences are stable for h ω_max ≤ 2: warn when the step exceeds it for the
  // stiffest mode of a flexible body (implicit schemes stay stable but do not resolve it).
  for (const core::Body& b : model.bodies()) {
    if (!b.is_flexible() || b.natural_frequencies().size() == 0) continue;
    const double omega_max = b.natural_frequencies().maxCoeff();
    if (omega_max > 0.0 && options.dt > 2.0 / omega_max) {
      std::cerr << "flexref: warning: step " << options.dt
                << " s exceeds 2/omega_max = " << 2.0 / omega_max << " s of flexible body "
                << b.name() << " (omega_max = " << omega_max
                << " rad/s): explicit central differences would be unstable and the highest "
                   "modes are not resolved\n";
    }
  }
  // The same for the stiffest mode of every contact and joint (penalty elements).
  for (const scene::PenaltyMode& m : scene.penalty_modes) {
    if (options.dt > m.step_limit) {
      std::cerr << "flexref: warning: step " << options.dt
                << " s exceeds 2/omega = " << m.step_limit << " s of " << m.label
                << " (omega = " << m.frequency
                << " rad/s): explicit central differences would be unstable and the " << m.kind
                << " is not resolved\n";
    }
  }
  auto stepper = lie::make_stepper(options.scheme, model);
  const double start = studies::thread_cpu_seconds();
  const core::Trajectory trajectory = lie::run_scheme(model, *stepper, options.dt, times);
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
      .set("steps", std::lround((times.back() - times.front()) / options.dt))
      .set("cpu_seconds", cpu);
  studies::add_versions(record);
  record.write(options.output + ".meta.toml");

  std::cout << "run " << scene.name << " with " << options.scheme
            << (model.has_flexible_bodies()
                    ? std::string(" (") + core::to_string(model.formulation()) + " model)"
                    : std::string())
            << ", dt " << options.dt
            << " s: " << std::lround((times.back() - times.front()) / options.dt) << " steps, "
            << cpu << " s CPU; energy " << e_first << " -> " << e_last << " J; wrote "
            << options.output << "\n";
  return kExitOk;
}

}  // namespace flexref::app
