#include "examples/simbody/simbody_engine.hpp"

#include <CLI/CLI.hpp>

#include "core/error.hpp"
#include "examples/engine_adapter/scene_mapping.hpp"
#include "examples/simbody/simbody_mapping.hpp"
#include "examples/simbody/simbody_system.hpp"

namespace flexref::engines {

std::vector<std::pair<std::string, std::string>> SimbodyEngine::integrators() const {
  return simbody_integrators();
}

void SimbodyEngine::add_options(CLI::App& app) {
  app.add_option("--accuracy", accuracy_,
                 "Simbody's setAccuracy (default: Simbody's 1e-3); in fixed-step mode it still "
                 "decides projection and Verlet's velocity iteration (docs/engines.md)")
      ->check(CLI::PositiveNumber);
  app.add_option("--constraint-tolerance", constraint_tolerance_,
                 "Simbody's setConstraintTolerance, projecting the loop closures after every "
                 "step (default: Simbody's accuracy/10, projected only beyond it; "
                 "docs/engines.md)")
      ->check(CLI::PositiveNumber);
}

void SimbodyEngine::check_mappable(const scene::Scene& scene, const std::string&) const {
  check_simbody_mappable(scene);
}

void SimbodyEngine::simulate(const scene::Scene& scene, const StepPlan& plan,
                             const std::string& integrator, const Recorder& record) {
  SimbodyOptions options;
  options.integrator = integrator;
  options.accuracy = accuracy_;
  options.constraint_tolerance = constraint_tolerance_;
  try {
    run_simbody(rigid_scene(scene, simbody_joint_support()), plan, options, record);
  } catch (const SimbodyFailure& e) {
    throw core::SolverError(version() + " " + integrator, e.time(), e.step(), e.what());
  }
}

}  // namespace flexref::engines
