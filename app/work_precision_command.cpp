#include "app/work_precision_command.hpp"

#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "core/output_times.hpp"
#include "io/atomic_file.hpp"
#include "scene/scene_reader.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/trajectory_table.hpp"
#include "studies/versions.hpp"
#include "studies/work_precision.hpp"

namespace flexref::app {
int work_precision_command(const WorkPrecisionOptions& app_options) {
  const scene::Scene scene =
      scene::read_scene(app_options.scene, parse_formulation(app_options.model));
  const core::Model& model = *scene.model;
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);

  studies::WorkPrecisionOptions study;
  study.schemes = app_options.schemes;
  study.h0 = app_options.dt;
  study.levels = app_options.levels;
  study.solvers = app_options.solvers;
  study.tolerances = app_options.tolerances;
  study.repeats = app_options.repeats;
  study.metric = app_options.metric;
  study.reference_solver =
      reference_solver_for(model, app_options.reference_solver, "--reference-solver");
  study.reference_rtol = app_options.reference_rtol;
  study.jobs = app_options.jobs > 0 ? app_options.jobs : studies::default_jobs();
  study.progress = true;
  const studies::WorkPrecisionResult result = studies::run_work_precision(model, times, study);

  std::filesystem::create_directories(app_options.out_dir);
  const std::filesystem::path dir(app_options.out_dir);
  const std::string table = format_work_precision_table(result);
  std::ostringstream settings;
  settings.precision(17);
  settings << scene_metadata(app_options.scene, scene)
           << "\n[study]\nkind = \"work-precision\"\nschemes = " << toml_string_array(study.schemes)
           << "\ndt = " << study.h0 << "\nlevels = " << study.levels
           << "\nsolvers = " << toml_string_array(study.solvers)
           << "\ntolerances = " << toml_number_array(study.tolerances)
           << "\nrepeats = " << study.repeats << "\nmetric = \"" << study.metric
           << "\"\njobs = " << study.jobs
           << "\ncpu_time = \"thread CPU time of the integration only, minimum over repeats\""
           << "\ntarget_errors = " << toml_number_array(studies::default_target_errors()) << "\n\n"
           << studies::reference_toml(result.reference) << "\n"
           << studies::versions_toml();

  const std::string csv_path = (dir / "work_precision.csv").string();
  io::write_file_atomically(csv_path, studies::work_precision_csv(result));
  io::write_file_atomically((dir / "work_precision.txt").string(), table);
  io::write_file_atomically((dir / "study.toml").string(), settings.str());
  studies::write_csv(result.reference.table, (dir / "reference.csv").string());
  const std::string png = (dir / "work_precision.png").string();
  const studies::PlotOutcome plot =
      studies::run_plot_script("plot_work_precision.py",
                               {csv_path, png, "work-precision: " + scene.name, study.metric}, png);

  std::cout << "work-precision " << scene.name << "\n" << table;
  std::cout << "wrote " << csv_path << ", work_precision.txt, study.toml, reference.csv";
  std::cout << (plot.ok ? ", " + plot.message : "") << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  return kExitOk;
}

}  // namespace flexref::app
