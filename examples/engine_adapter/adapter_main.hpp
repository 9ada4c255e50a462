#pragma once
/// \file adapter_main.hpp
/// The command line every engine adapter shares:
///
///     PROGRAM SCENE DT OUTPUT [--integrator NAME] [--max-steps N]
///
/// reads SCENE with flexref's scene reader, checks DT against the scene's output grid and load
/// switches (lie::validate_step_grid: every output time and switch is a whole number of steps),
/// asks the engine whether it can map the scene, runs it and writes OUTPUT under the trajectory
/// contract. Exit codes are flexref's (docs/cli.md): 0 success, 1 bad input (scene, a value the run
/// cannot honour, a part of the scene the engine cannot map), 2 usage, 3 the engine failed or
/// its state turned non-finite (time and step), 5 the output cannot be written.
#include "examples/engine_adapter/engine.hpp"

namespace flexref::engines {

int adapter_main(int argc, char** argv, Engine& engine);

}  // namespace flexref::engines
