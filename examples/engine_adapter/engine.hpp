#pragma once
/// \file engine.hpp
/// What an engine adapter (examples/mujoco, examples/simbody) implements: the mapping of a
/// flexref scene onto the engine and a fixed-step run on flexref's output grid. The shared
/// program around it (adapter_main.hpp) reads the scene with flexref's own reader, checks the
/// step, writes the trajectory contract (docs/external.md) and turns failures into the exit
/// codes of flexref's command line (docs/cli.md, "Exit codes").
#include <stdexcept>
#include <string>
#include <vector>

#include "examples/engine_adapter/rigid_scene.hpp"
#include "scene/scene.hpp"

namespace CLI {
class App;
}

namespace flexref::engines {

/// A part of the scene the engine cannot reproduce exactly: names the table it came from
/// (file, line, key) and says why. Exit code 1.
class MappingError : public std::runtime_error {
 public:
  MappingError(const scene::SpecSource& source, const std::string& why);
  /// For an option the engine cannot honour on this scene: "OPTION VALUE: why".
  MappingError(const std::string& option, const std::string& why);
};

class Engine {
 public:
  virtual ~Engine() = default;
  /// The program's name in messages ("flexref_mujoco").
  virtual std::string program() const = 0;
  /// The engine and its version, e.g. "MuJoCo 2.2.2".
  virtual std::string version() const = 0;
  /// The integrators --integrator accepts, with a one-line description each; the first is the
  /// default.
  virtual std::vector<std::pair<std::string, std::string>> integrators() const = 0;
  /// The engine's own options beside --integrator (Simbody's --accuracy), none by default.
  virtual void add_options(CLI::App& app) { (void)app; }
  /// Throws MappingError for the first part of the scene it cannot map, or when `integrator`
  /// cannot be run on it.
  virtual void check_mappable(const scene::Scene& scene, const std::string& integrator) const = 0;
  /// Runs the scene at the plan's fixed step and calls `record` at every output time. Throws
  /// core::SolverError (time, step, why) when the engine fails or its state turns non-finite.
  virtual void simulate(const scene::Scene& scene, const StepPlan& plan,
                        const std::string& integrator, const Recorder& record) = 0;
};

}  // namespace flexref::engines
