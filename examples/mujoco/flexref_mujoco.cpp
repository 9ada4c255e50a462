/// \file flexref_mujoco.cpp
/// `flexref_mujoco SCENE DT OUTPUT [--integrator rk4|euler|implicit|implicitfast]
/// [--solref TIMECONST DAMPRATIO] [--solimp DMIN DMAX WIDTH [MID POWER]]`: a flexref scene
/// integrated by MuJoCo at a fixed step, written under flexref's trajectory contract, so that
/// `flexref converge --external` and `work-precision --external` can verify MuJoCo's
/// integrators (docs/engines.md).
#include "examples/engine_adapter/adapter_main.hpp"
#include "examples/mujoco/mujoco_engine.hpp"

int main(int argc, char** argv) {
  flexref::engines::MujocoEngine engine;
  return flexref::engines::adapter_main(argc, argv, engine);
}
