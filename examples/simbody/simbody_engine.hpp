#pragma once
/// \file simbody_engine.hpp
/// Simbody through flexref's trajectory contract (docs/engines.md): the checks of
/// simbody_mapping.hpp, then the scene as plain data to simbody_system.hpp, which builds and
/// integrates the MultibodySystem at the fixed step.
#include "examples/engine_adapter/engine.hpp"

namespace flexref::engines {

class SimbodyEngine final : public Engine {
 public:
  std::string program() const override { return "flexref_simbody"; }
  std::string version() const override { return "Simbody 3.7"; }
  std::vector<std::pair<std::string, std::string>> integrators() const override;
  void add_options(CLI::App& app) override;
  void check_mappable(const scene::Scene& scene, const std::string& integrator) const override;
  void simulate(const scene::Scene& scene, const StepPlan& plan, const std::string& integrator,
                const Recorder& record) override;

 private:
  double accuracy_ = 0.0;              ///< 0: Simbody's default
  double constraint_tolerance_ = 0.0;  ///< 0: Simbody's default
};

}  // namespace flexref::engines
