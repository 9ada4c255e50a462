#include <cmath>
#include <ctime>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "app/scene_reader.hpp"
#include "core/output_times.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "studies/parallel.hpp"
#include "studies/trajectory_table.hpp"
#include "studies/versions.hpp"

namespace flexref::app {

int run_command(const RunOptions& options) {
  const Scene scene = read_scene(options.scene);
  const core::Model& model = *scene.model;
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);
  auto stepper = lie::make_stepper(options.scheme, model);
  const double start = studies::thread_cpu_seconds();
  const core::Trajectory trajectory = lie::run_scheme(model, *stepper, options.dt, times);
  const double cpu = studies::thread_cpu_seconds() - start;
  const studies::TrajectoryTable table = studies::tabulate(model, trajectory);
  studies::write_csv(table, options.output);

  const int energy = table.column("energy");
  const double e_first = table.rows.front()[static_cast<std::size_t>(energy)];
  const double e_last = table.rows.back()[static_cast<std::size_t>(energy)];
  std::ostringstream meta;
  meta.precision(17);
  meta << scene_metadata(options.scene, scene.name) << "\n[integrator]\nkind = \"scheme\"\n"
       << "scheme = \"" << options.scheme << "\"\ndt = " << options.dt
       << "\nsteps = " << std::lround((times.back() - times.front()) / options.dt)
       << "\ncpu_seconds = " << cpu << "\n\n"
       << studies::versions_toml();
  studies::write_file_atomically(options.output + ".meta.toml", meta.str());

  std::cout << "run " << scene.name << " with " << options.scheme << ", dt " << options.dt
            << " s: " << std::lround((times.back() - times.front()) / options.dt) << " steps, "
            << cpu << " s CPU; energy " << e_first << " -> " << e_last << " J; wrote "
            << options.output << "\n";
  return kExitOk;
}

}  // namespace flexref::app
