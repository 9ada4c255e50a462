#pragma once
/// \file reference_solver.hpp
/// The reference integrators (docs/design/schemes.md, "Reference integrators";
/// docs/references.md): IDA on the DAE form, CVODE (Adams or BDF with projection) and ARKODE's
/// explicit Fehlberg 13-7-8 on the ODE form, Boost.Odeint RKF7(8) with an order-8 continuous
/// extension on the ODE form. Each stops and restarts at every known load discontinuity and at
/// every located contact event, and writes the state at the requested output times from its
/// own dense output or by stopping exactly on them, never by interpolating a coarse output;
/// the output grid never sets the step sequence (except ARKODE's exact stops).
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::reference {

class OdeJacobian;

/// CVODE's linear multistep family (docs/references.md, "CVODE: Adams or BDF").
enum class CvodeMethod {
  kAuto,   ///< chosen from the model (choose_cvode_method, reference/method_choice.hpp)
  kAdams,  ///< Adams–Moulton orders 1–12, no projection: |θ| is a first integral
  kBdf,    ///< BDF orders 1–5 with the projection of θ onto the unit sphere
};

struct SolverOptions {
  double rtol = 1e-10;
  /// Absolute tolerance; a negative value means atol = rtol (the states are O(1) in SI).
  double atol = -1.0;
  /// Most internal steps between two consecutive output times (SUNDIALS' mxstep meaning).
  long max_steps = 50'000'000;
  /// CVODE only.
  CvodeMethod cvode_method = CvodeMethod::kAuto;
  /// CVODE and IDA: ∂f/∂y of the ODE form instead of difference quotients (ode_jacobian.hpp);
  /// not owned, must outlive the solve.
  const OdeJacobian* jacobian = nullptr;
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
  std::string solver;  ///< "ida", "cvode", "arkode", "odeint", "exact"
  /// The method within the solver: "bdf" (ida), "adams" or "bdf" (cvode),
  /// "erk-fehlberg-13-7-8" (arkode), "rkf78" (odeint), "analytic" (exact).
  std::string method;
  /// Why this method (CVODE's automatic choice names the model's stiff element, if any).
  std::string method_reason;
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
ReferenceRun solve_arkode(const core::Model& model, const std::vector<double>& output_times,
                          const SolverOptions& options);
ReferenceRun solve_odeint(const core::Model& model, const std::vector<double>& output_times,
                          const SolverOptions& options);

/// "auto", "adams", "bdf"; and back (std::invalid_argument for another name).
const char* to_string(CvodeMethod method);
CvodeMethod parse_cvode_method(const std::string& name);

}  // namespace flexref::reference
