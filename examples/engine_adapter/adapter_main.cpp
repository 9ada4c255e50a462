#include "examples/engine_adapter/adapter_main.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <iostream>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "examples/engine_adapter/trajectory_writer.hpp"
#include "lie/run_scheme.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::engines {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitInputError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitSolverError = 3;
constexpr int kExitOutputError = 5;

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

StepPlan make_plan(const scene::Scene& scene, double dt, long max_steps) {
  StepPlan plan;
  plan.dt = dt;
  plan.output_times = core::output_times(scene.end_time, scene.output_step);
  // Throws std::invalid_argument naming the output time or switch that is off the step grid.
  plan.step_count = lie::validate_step_grid(*scene.model, dt, plan.output_times);
  if (plan.step_count > max_steps) {
    throw std::invalid_argument("DT = " + std::to_string(dt) + " s needs " +
                                std::to_string(plan.step_count) + " steps, more than --max-steps " +
                                std::to_string(max_steps));
  }
  for (double t : plan.output_times) plan.output_steps.push_back(std::lround(t / dt));
  for (double d : scene.model->discontinuities()) {
    if (d > 0.0 && d <= scene.end_time) plan.switch_steps.push_back(std::lround(d / dt));
  }
  std::sort(plan.switch_steps.begin(), plan.switch_steps.end());
  plan.switch_steps.erase(std::unique(plan.switch_steps.begin(), plan.switch_steps.end()),
                          plan.switch_steps.end());
  return plan;
}

}  // namespace

int adapter_main(int argc, char** argv, Engine& engine) {
  const auto integrators = engine.integrators();
  std::string scene_path, output;
  double dt = 0.0;
  std::string integrator = integrators.front().first;
  long max_steps = 10'000'000;
  std::string integrator_help = "the engine's integrator:";
  std::vector<std::string> names;
  for (const auto& [name, description] : integrators) {
    integrator_help += "\n  " + name + ": " + description;
    names.push_back(name);
  }
  CLI::App app{engine.version() + " through flexref's trajectory contract (docs/engines.md)",
               engine.program()};
  app.add_option("scene", scene_path, "flexref scene file (TOML)")->required();
  app.add_option("dt", dt, "the fixed step [s]; every output time must be a whole number of steps")
      ->required()
      ->check(CLI::PositiveNumber);
  app.add_option("output", output, "the CSV file to write (trajectory contract, docs/external.md)")
      ->required();
  app.add_option("--integrator", integrator, integrator_help)
      ->check(CLI::IsMember(names))
      ->capture_default_str();
  app.add_option("--max-steps", max_steps, "refuse a run of more steps")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  engine.add_options(app);
  app.footer(
      "exit codes: 0 success, 1 bad input or a scene the engine cannot map, 2 usage, 3 the "
      "engine failed, 5 the output cannot be written");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  const std::string who = engine.program() + ": ";
  try {
    const scene::Scene scene = scene::read_scene(scene_path);
    StepPlan plan;
    try {
      plan = make_plan(scene, dt, max_steps);
    } catch (const std::invalid_argument& e) {
      std::cerr << who << scene_path << ": DT: " << e.what() << "\n";
      return kExitInputError;
    }
    engine.check_mappable(scene, integrator);
    TrajectoryWriter writer(output, scene);
    const std::string label = engine.version() + " " + integrator;
    // The CPU time of the engine's work alone, as flexref times its own schemes: building the
    // engine's model and stepping it, without reading the scene or writing the file
    // (reported as `# cpu_seconds`, docs/external.md).
    double writing_seconds = 0.0;
    const double start = process_cpu_seconds();
    engine.simulate(scene, plan, integrator,
                    [&](std::size_t k, double t_engine, const std::vector<BodySample>& bodies) {
                      const double before = process_cpu_seconds();
                      writer.write_row(t_engine, plan.output_steps[k], bodies, label);
                      writing_seconds += process_cpu_seconds() - before;
                    });
    writer.write_cpu_seconds(process_cpu_seconds() - start - writing_seconds);
    writer.commit();
    std::cout << who << engine.version() << ", integrator " << integrator << ", " << plan.step_count
              << " steps of " << dt << " s: wrote " << output << "\n";
    return kExitOk;
  } catch (const core::InputError& e) {
    std::cerr << who << e.what() << "\n";
    return kExitInputError;
  } catch (const MappingError& e) {
    std::cerr << who << e.what() << "\n";
    return kExitInputError;
  } catch (const core::SolverError& e) {
    std::cerr << who << e.what() << "\n";
    return kExitSolverError;
  } catch (const OutputError& e) {
    std::cerr << who << e.what() << "\n";
    return kExitOutputError;
  }
}

}  // namespace flexref::engines
