#pragma once
/// \file solver_options.hpp
/// Reference-solver options for tests that vary only the relative tolerance.
#include "reference/reference_solver.hpp"

namespace flexref::testing {

/// Internal steps a test's solver may take between two output times. The library's default
/// (50 million) lets a solver whose steps collapse run on for hours — with the point rows' γ
/// sign changed, CVODE crawled through jointed_contact_test for over 27 minutes — where a test
/// must fail: with this budget it stops there in 0.3 s (CV_TOO_MUCH_WORK at t = 0.069). Every
/// test that takes its options from with_rtol passes with a budget of 1e3 (measured on the
/// constraint and reference programs); 1e4 leaves a factor 10.
inline constexpr long kTestStepBudget = 10'000;

/// reference::SolverOptions with relative tolerance `rtol`, the test step budget above, and
/// every other option at its default.
inline reference::SolverOptions with_rtol(double rtol) {
  reference::SolverOptions options;
  options.rtol = rtol;
  options.max_steps = kTestStepBudget;
  return options;
}

}  // namespace flexref::testing
