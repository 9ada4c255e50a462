#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "core/output_times.hpp"
#include "io/atomic_file.hpp"
#include "scene/scene_reader.hpp"
#include "studies/convergence.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/trajectory_table.hpp"
#include "studies/versions.hpp"

namespace flexref::app {

int converge_command(const ConvergeOptions& options) {
  const scene::Scene scene = scene::read_scene(options.scene, parse_formulation(options.model));
  const core::Model& model = *scene.model;
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);

  studies::ConvergenceOptions study;
  study.schemes = options.schemes;
  study.h0 = options.dt;
  study.levels = options.levels;
  study.metric = options.metric;
  study.reference_solver =
      reference_solver_for(model, options.reference_solver, "--reference-solver");
  study.reference_rtol = options.reference_rtol;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  study.progress = true;
  const studies::ConvergenceResult result = studies::run_convergence(model, times, study);

  std::filesystem::create_directories(options.out_dir);
  const std::filesystem::path dir(options.out_dir);
  const std::string table = format_convergence_table(result);
  std::ostringstream settings;
  settings.precision(17);
  settings << scene_metadata(options.scene, scene) << "\n[study]\nkind = \"converge\"\n"
           << "schemes = " << toml_string_array(options.schemes) << "\ndt = " << options.dt
           << "\nlevels = " << options.levels << "\nmetric = \"" << options.metric
           << "\"\njobs = " << study.jobs << "\n\n"
           << studies::reference_toml(result.reference) << "\n"
           << studies::versions_toml();

  const std::string csv_path = (dir / "convergence.csv").string();
  io::write_file_atomically(csv_path, studies::convergence_csv(result));
  io::write_file_atomically((dir / "convergence.txt").string(), table);
  io::write_file_atomically((dir / "study.toml").string(), settings.str());
  studies::write_csv(result.reference.table, (dir / "reference.csv").string());
  const std::string png = (dir / "convergence.png").string();
  const studies::PlotOutcome plot = studies::run_plot_script(
      "plot_convergence.py", {csv_path, png, "convergence: " + scene.name}, png);

  std::cout << "converge " << scene.name << "\n" << table;
  std::cout << "wrote " << csv_path << ", convergence.txt, study.toml, reference.csv";
  std::cout << (plot.ok ? ", " + plot.message : "") << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  return kExitOk;
}

}  // namespace flexref::app
