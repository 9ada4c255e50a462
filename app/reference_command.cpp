#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "studies/certified_reference.hpp"
#include "studies/progress.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::app {

int reference_command(const ReferenceOptions& options) {
  const scene::Scene scene = load_scene(options.scene, parse_formulation(options.model));
  const core::Model& model = *scene.model;
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);
  const std::string solver = reference_solver_for(model, options.solver, "--solver");
  check_output_files({options.output, options.output + ".meta.toml"});
  reference::SolverOptions solver_options;
  solver_options.rtol = options.rtol;
  solver_options.atol = options.atol;

  studies::CertifiedReference ref;
  {
    const studies::Progress progress(
        "reference: " + solver + (options.estimate ? " and its error estimate (3 solves)" : ""), 0,
        "");
    if (options.estimate) {
      ref = studies::certified_reference(model, times, solver, solver_options, "rotation+points");
    } else {
      ref.run = reference::solve_reference(solver, model, times, solver_options);
      ref.table = studies::tabulate(model, ref.run.trajectory);
    }
  }
  studies::write_csv(ref.table, options.output);

  const auto& st = ref.run.stats;
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("integrator")
      .set("kind", "reference")
      .set("solver", ref.run.solver)
      .set("rtol", options.rtol)
      .set("atol", solver_options.absolute_tolerance())
      .set("steps", st.steps)
      .set("rhs_evaluations", st.rhs_evaluations)
      .set("jacobian_evaluations", st.jacobian_evaluations)
      .set("error_test_failures", st.error_test_failures)
      .set("nonlinear_failures", st.nonlinear_failures)
      .set("cpu_seconds", st.cpu_seconds)
      .set("events", ref.run.event_times.size())
      .set("event_times", ref.run.event_times);
  if (options.estimate) {
    const auto& e = ref.estimate;
    record.table("error_estimate")
        .set("metric", e.metric)
        .set("estimate", e.estimate())
        .set("vs_tighter", e.vs_tighter)
        .set("tighter_solver", e.tighter_solver)
        .set("tighter_rtol", e.tighter_rtol)
        .set("vs_other_solver", e.vs_other_solver)
        .set("other_rtol", e.other_rtol)
        .set("other_solver", e.other_solver);
  }
  record.table("columns")
      .set("names", ref.table.columns)
      .set("units", studies::trajectory_units(model));
  studies::add_versions(record);
  record.write(options.output + ".meta.toml");

  std::cout << "reference " << scene.name << " with " << ref.run.solver;
  if (model.has_flexible_bodies()) {
    std::cout << " (" << core::to_string(model.formulation()) << " model)";
  }
  if (ref.run.solver == "exact") {
    std::cout << " (analytic, " << st.steps << " output times)";
  } else {
    std::cout << " (rtol " << options.rtol << "): " << st.steps << " steps, " << st.rhs_evaluations
              << " evaluations";
  }
  if (model.switching_function_count() > 0 || !ref.run.event_times.empty()) {
    std::cout << ", " << ref.run.event_times.size() << " events located";
  }
  std::cout << ", " << st.cpu_seconds << " s CPU; wrote " << options.output << "\n";
  if (options.estimate) {
    const auto& e = ref.estimate;
    std::cout << "estimated error (" << e.metric << "): " << e.estimate() << "  [vs "
              << e.tighter_solver << " at rtol " << e.tighter_rtol << ": " << e.vs_tighter
              << "; vs " << e.other_solver << " at rtol " << e.other_rtol << ": "
              << e.vs_other_solver << "]"
              << (e.exact ? " (exact solution: the smaller difference bounds its error)" : "")
              << "\n";
  }
  return kExitOk;
}

}  // namespace flexref::app
