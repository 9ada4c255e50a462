#pragma once
/// \file reference_solver.hpp
/// The reference integrators (docs/design/schemes.md, "Reference integrators"): IDA on the DAE
/// form, CVODE on the ODE form with projection, Boost.Odeint RKF7(8) on the ODE form. Each
/// stops and restarts at every known load discontinuity and writes the state at the requested
/// output times (by the solver's own dense output or by stepping exactly onto them, never by
/// interpolating a coarse output).
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::reference {

struct SolverOptions {
  double rtol = 1e-10;
  /// Absolute tolerance; a negative value means atol = rtol (the states are O(1) in SI).
  double atol = -1.0;
  /// Most internal steps between two consecutive output times (SUNDIALS' mxstep meaning).
  long max_steps = 50'000'000;
  double absolute_tolerance() const { return atol < 0.0 ? rtol : atol; }
};

struct SolverStats {
  long steps = 0;
  long rhs_evaluations = 0;
  long jacobian_evaluations = 0;
  long error_test_failures = 0;
  long nonlinear_failures = 0;
  long events = 0;           ///< zeros of switching functions located (contact onset and release)
  double cpu_seconds = 0.0;  ///< process CPU time of the integration, output excluded
};

struct ReferenceRun {
  std::string solver;  ///< "ida", "cvode", "odeint", "exact"
  SolverOptions options;
  core::Trajectory trajectory;
  SolverStats stats;
  /// Times of the located switching events (contact onset and release), ascending; the solver
  /// restarted at each (no step straddles one).
  std::vector<double> event_times;
};

/// Throws core::SolverError (time, step, the solver's message) when the solver fails.
ReferenceRun solve_ida(const core::Model& model, const std::vector<double>& output_times,
                       const SolverOptions& options);
ReferenceRun solve_cvode(const core::Model& model, const std::vector<double>& output_times,
                         const SolverOptions& options);
ReferenceRun solve_odeint(const core::Model& model, const std::vector<double>& output_times,
                          const SolverOptions& options);

}  // namespace flexref::reference
