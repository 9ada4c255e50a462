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
class SolveProgress;

/// CVODE's linear multistep family (docs/references.md, "CVODE: Adams or BDF").
enum class CvodeMethod {
  kAuto,   ///< chosen from the model (choose_cvode_method, reference/method_choice.hpp)
  kAdams,  ///< Adams–Moulton orders 1–12, no projection: |θ| is a first integral
  kBdf,    ///< BDF orders 1–5 with the projection of θ onto the unit sphere
  /// BDF orders 1–2 with the projection: A-stable, for undamped modes far above every rate the
  /// solution must resolve (BDF3–5 are unstable on part of the imaginary axis); also IDA's cap.
  kBdf2,
};

/// ARKODE's method (docs/references.md, "ARKODE", "Stiff oscillatory scenes").
enum class ArkodeMethod {
  kAuto,    ///< chosen from the model and output grid (choose_arkode_method, method_choice.hpp)
  kErk,     ///< ERKStep, Fehlberg 13-7-8 (explicit, order 8)
  kEsdirk,  ///< ARKStep, ESDIRK5(4)7L[2]SA (implicit, L-stable, order 5)
};

/// IDA's Newton matrix on a model with ideal joints (docs/references.md, "IDA";
/// choose_ida_newton_jacobian, method_choice.hpp).
enum class NewtonMatrix {
  kAuto,    ///< sparse (measured never slower on a jointed model)
  kDense,   ///< IDA's difference quotients, dense LU
  kSparse,  ///< coloured difference quotients, KLU (reference/dae_coloured_jacobian.hpp)
};

/// The coordinates CVODE integrates a model of rigid bodies on ideal joints in
/// (docs/reduced_coordinates.md, "In the product"; reference/reduced_cvode.hpp).
enum class Coordinates {
  /// Joint coordinates where they apply — rigid bodies on ideal joints, no contact, Adams (a
  /// spectrum that is not stiff) — else maximal.
  kAuto,
  kMaximal,  ///< the bodies' own states, every joint row enforced with multipliers
  /// The spanning tree's joint coordinates, the loop closures with multipliers; refused
  /// (std::invalid_argument) where they do not apply.
  kJoint,
};

struct SolverOptions {
  double rtol = 1e-10;
  /// Absolute tolerance; a negative value means atol = rtol (the states are O(1) in SI).
  double atol = -1.0;
  /// Most internal steps between two consecutive output times (SUNDIALS' mxstep meaning).
  long max_steps = 50'000'000;
  /// CVODE's method; for IDA, kBdf and kBdf2 cap its order at 5 and 2 (kAdams is refused),
  /// kAuto chooses from the model (reference/method_choice.hpp).
  CvodeMethod cvode_method = CvodeMethod::kAuto;
  ArkodeMethod arkode_method = ArkodeMethod::kAuto;
  /// CVODE, IDA and ARKODE's ESDIRK: ∂f/∂y of the ODE form instead of the structured Jacobian
  /// (flexible models) or difference quotients (rigid ones) (ode_jacobian.hpp); not owned, must
  /// outlive the solve.
  const OdeJacobian* jacobian = nullptr;
  /// IDA on ideal joints: its Newton matrix dense or sparse (kAuto: by the number of bodies).
  NewtonMatrix newton_matrix = NewtonMatrix::kAuto;
  /// CVODE on ideal joints: maximal or joint coordinates (solve_reference chooses; solve_cvode
  /// is the maximal form).
  Coordinates coordinates = Coordinates::kAuto;
  /// Where a progress line follows the solve (solve_progress.hpp): the solver stores the time
  /// it reached at each output time. Not owned; solve_reference does not keep it in the run.
  SolveProgress* progress = nullptr;
  double absolute_tolerance() const { return atol < 0.0 ? rtol : atol; }
};

struct SolverStats {
  long steps = 0;
  long rhs_evaluations = 0;
  long jacobian_evaluations = 0;
  long error_test_failures = 0;
  long nonlinear_failures = 0;
  long events = 0;  ///< zeros of switching functions located (contact onset and release)
  /// Process CPU time of the integration and its output states (setup and checks excluded).
  double cpu_seconds = 0.0;
};

struct ReferenceRun {
  std::string solver;  ///< "ida", "cvode", "arkode", "odeint", "exact"
  /// The method within the solver: "bdf" or "bdf2" (ida), "adams", "bdf" or "bdf2" (cvode),
  /// "erk-fehlberg-13-7-8" or "esdirk547l2sa-7-4-5" (arkode), "rkf78" (odeint), "analytic"
  /// (exact).
  std::string method;
  /// Why this method (CVODE's and IDA's automatic choice names the model's stiff element, if
  /// any).
  std::string method_reason;
  /// The implicit solvers' Newton systems: "structured" (reference/structured_jacobian.hpp
  /// with the structured Newton solve), "difference quotients" (the solver's own, dense LU),
  /// "user" (SolverOptions::jacobian, dense LU); empty for the explicit ones.
  std::string jacobian;
  /// "maximal" (the bodies' states) or "joint" (joint coordinates, reference/reduced_cvode.hpp),
  /// and why (for the metadata).
  std::string coordinates = "maximal";
  std::string coordinates_reason;
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

/// "auto", "adams", "bdf", "bdf2"; and back (std::invalid_argument for another name).
const char* to_string(CvodeMethod method);
CvodeMethod parse_cvode_method(const std::string& name);
/// "auto", "erk", "esdirk"; and back (std::invalid_argument for another name).
const char* to_string(ArkodeMethod method);
ArkodeMethod parse_arkode_method(const std::string& name);
/// "auto", "maximal", "joint"; and back (std::invalid_argument for another name).
const char* to_string(Coordinates coordinates);
Coordinates parse_coordinates(const std::string& name);

}  // namespace flexref::reference
