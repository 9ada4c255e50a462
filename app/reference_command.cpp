#include <cmath>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "core/output_times.hpp"
#include "io/atomic_file.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "studies/certified_reference.hpp"
#include "studies/trajectory_table.hpp"
#include "studies/versions.hpp"

namespace flexref::app {

int reference_command(const ReferenceOptions& options) {
  const scene::Scene scene = scene::read_scene(options.scene, parse_formulation(options.model));
  const core::Model& model = *scene.model;
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);
  const std::string solver = reference_solver_for(model, options.solver, "--solver");
  reference::SolverOptions solver_options;
  solver_options.rtol = options.rtol;
  solver_options.atol = options.atol;
  solver_options.cvode_method = reference::parse_cvode_method(options.method);

  studies::CertifiedReference ref;
  if (options.estimate) {
    ref = studies::certified_reference(model, times, solver, solver_options, "rotation+points");
  } else {
    ref.run = reference::solve_reference(solver, model, times, solver_options);
    ref.table = studies::tabulate(model, ref.run.trajectory);
  }
  studies::write_csv(ref.table, options.output);

  const auto& st = ref.run.stats;
  std::ostringstream meta;
  meta.precision(17);
  meta << scene_metadata(options.scene, scene) << "\n[integrator]\nkind = \"reference\"\n"
       << "solver = \"" << ref.run.solver << "\"\nmethod = \"" << ref.run.method
       << "\"\nmethod_reason = \"" << ref.run.method_reason << "\"\nrtol = " << options.rtol
       << "\natol = " << solver_options.absolute_tolerance() << "\nsteps = " << st.steps
       << "\nrhs_evaluations = " << st.rhs_evaluations
       << "\njacobian_evaluations = " << st.jacobian_evaluations
       << "\nerror_test_failures = " << st.error_test_failures
       << "\nnonlinear_failures = " << st.nonlinear_failures << "\ncpu_seconds = " << st.cpu_seconds
       << "\nevents = " << ref.run.event_times.size()
       << "\nevent_times = " << toml_number_array(ref.run.event_times) << "\n";
  if (options.estimate) {
    const auto& e = ref.estimate;
    // estimate = inf: no check was a different, more accurate solution (see method).
    meta << "\n[error_estimate]\nmetric = \"" << e.metric << "\"\nestimate = " << e.estimate()
         << "\nmethod = \"" << e.method << "\"\n";
    for (const auto& c : e.checks) {
      meta << "\n[[error_estimate.check]]\nrole = \"" << c.role << "\"\nsolver = \"" << c.solver
           << "\"\nmethod = \"" << c.method << "\"\nrtol = " << c.rtol << "\nsteps = " << c.steps
           << "\ndistance = " << c.distance << "\nused = " << (c.used ? "true" : "false")
           << "\nnote = \"" << c.note << "\"\n";
    }
  }
  meta << "\n" << studies::versions_toml();
  io::write_file_atomically(options.output + ".meta.toml", meta.str());

  std::cout << "reference " << scene.name << " with " << ref.run.solver << " (" << ref.run.method
            << ")";
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
  if (ref.run.solver == "cvode") std::cout << "method: " << ref.run.method_reason << "\n";
  if (options.estimate) {
    const auto& e = ref.estimate;
    std::cout << "estimated error (" << e.metric << "): " << studies::describe_estimate(e) << "\n";
    for (const auto& c : e.checks) {
      std::cout << "  " << c.role << ": " << c.solver;
      if (c.rtol > 0.0) std::cout << " rtol " << c.rtol;
      std::cout << ", " << c.steps << " steps, distance " << c.distance
                << (c.used ? "" : " (not used: " + c.note + ")") << "\n";
    }
  }
  return kExitOk;
}

}  // namespace flexref::app
