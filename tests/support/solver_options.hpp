#pragma once
/// \file solver_options.hpp
/// Reference-solver options for tests that vary only the relative tolerance.
#include "reference/reference_solver.hpp"

namespace flexref::testing {

/// Internal steps a test's solver may take between two output times. The library's default
/// (50 million) lets a solver whose steps collapse run on for hours; a test must fail instead.
/// Every unit test that runs a reference takes under ~5 s in Release at ≥ 1 µs per step, so
/// fewer than 5e6 steps in all and far fewer than 1e6 between two outputs: a collapse reaches
/// this budget within seconds and the solver reports it (SolverError).
inline constexpr long kTestStepBudget = 1'000'000;

/// reference::SolverOptions with relative tolerance `rtol`, the test step budget above, and
/// every other option at its default.
inline reference::SolverOptions with_rtol(double rtol) {
  reference::SolverOptions options;
  options.rtol = rtol;
  options.max_steps = kTestStepBudget;
  return options;
}

}  // namespace flexref::testing
