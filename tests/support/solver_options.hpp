#pragma once
/// \file solver_options.hpp
/// Reference-solver options for tests that vary only the relative tolerance.
#include "reference/reference_solver.hpp"

namespace flexref::testing {

/// reference::SolverOptions with relative tolerance `rtol` and every other option at its
/// default.
inline reference::SolverOptions with_rtol(double rtol) {
  reference::SolverOptions options;
  options.rtol = rtol;
  return options;
}

}  // namespace flexref::testing
