/// \file flexref_simbody.cpp
/// `flexref_simbody SCENE DT OUTPUT [--integrator NAME] [--accuracy A]
/// [--constraint-tolerance T]`: a flexref scene integrated by one of Simbody's integrators at a
/// fixed step, written under flexref's trajectory contract, so that `flexref converge
/// --external` and `work-precision --external` can verify them (docs/engines.md).
#include "examples/engine_adapter/adapter_main.hpp"
#include "examples/simbody/simbody_engine.hpp"

int main(int argc, char** argv) {
  flexref::engines::SimbodyEngine engine;
  return flexref::engines::adapter_main(argc, argv, engine);
}
