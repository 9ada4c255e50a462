#pragma once
/// \file certified_reference.hpp
/// A reference run with an estimate of its own error (docs/references.md, "Error estimates"),
/// in a named metric, from solutions that are genuinely more accurate and genuinely different:
///
///  - when the model has an exact solution (reference/exact_solution.hpp): the distance to it —
///    the run's true error, up to the exact solution's own (≲ 1e-13, exact_*_test.cpp);
///  - otherwise two checks, each at 100× tighter tolerance (clamped at 1e-14): the same solver
///    (a check that took the run's own number of steps is not a different solution and is not
///    used) and an independent solver (cross_check_solver). A check whose distance is exactly 0
///    is not used either. The estimate is twice the larger used distance: by the triangle
///    inequality, e_run ≤ d + e_check ≤ d + e_run/2 whenever the check is at least twice as
///    accurate as the run, so 2 d is never optimistic then.
///
/// An exact solution run as the reference itself is compared with three independent numerical
/// solutions at tight tolerance (ARKODE and Odeint at 1e-14, CVODE at 1e-13); its estimate is
/// the smallest distance, which bounds its own error plus the closest numerical solution's. The
/// estimate's method text names the solutions checked and the one that gave the value.
///
/// No usable check leaves the estimate at +inf (unknown): studies then certify nothing.
///
/// A dissipating model's energy balance B = E − E(0) + W_d − W_a (trajectory_table.hpp) is
/// recorded next to the estimate with the scale it is read against: the estimated error of its
/// terms, made the same way from the same checks — twice the larger distance in `energy`,
/// `dissipated_work` or `applied_work` (docs/references.md, "Energy balance"). A balance within a
/// small multiple of that scale is the integration error of its terms; one far above it would be
/// a leak in the bookkeeping itself, which the checks share.
#include <limits>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "reference/reference_solver.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {

/// One comparison solution behind an estimate.
struct EstimateCheck {
  std::string role;  ///< "exact", "tighter" (same solver) or "other" (another solver)
  std::string solver;
  std::string method;  ///< the solver's method (reference::ReferenceRun::method)
  double rtol = 0.0;   ///< 0 for the exact solution
  long steps = 0;
  double distance = 0.0;  ///< metric(run, this solution)
  /// rotation+points(run, this solution), rad + m, for the divergence guard of
  /// certified_reference alone (NaN when the tables have no rotation or point).
  double absolute_distance = std::numeric_limits<double>::quiet_NaN();
  /// L∞ distance in the energy balance's terms (energy, dissipated_work, applied_work), J; NaN
  /// for a model that does not dissipate.
  double energy_distance = 0.0;
  bool used = false;  ///< part of the estimate
  std::string note;   ///< why it is not used, when it is not
};

struct ReferenceEstimate {
  std::string metric;
  /// How the estimate was made, one line (for tables and metadata).
  std::string method;
  std::vector<EstimateCheck> checks;
  double value = 0.0;  ///< the estimated error; +inf when no check is usable
  bool exact = false;  ///< the run is an exact solution (see above)
  /// Largest |E − E(0) + W_d − W_a| over the run's output times, J (NaN: the model does not
  /// dissipate, so the table has no balance).
  double energy_balance = std::numeric_limits<double>::quiet_NaN();
  double energy_balance_time = std::numeric_limits<double>::quiet_NaN();  ///< where, s
  /// Estimated error of the balance's terms (see the file comment), J; +inf when no check is
  /// usable, NaN when the model does not dissipate.
  double energy_estimate = std::numeric_limits<double>::quiet_NaN();
  /// The estimate made the same way from the checks' absolute_distance (rad + m): what
  /// certified_reference holds against the solution's size at t0 (NaN when not measured).
  double absolute_value = std::numeric_limits<double>::quiet_NaN();
  double estimate() const { return value; }
};

struct CertifiedReference {
  reference::ReferenceRun run;
  TrajectoryTable table;
  ReferenceEstimate estimate;
};

/// The independent solver used to check `solver`: cvode, arkode → odeint; ida, odeint, exact →
/// cvode.
std::string cross_check_solver(const std::string& solver);

/// "auto" picks "exact" when the model has an exact solution, else
/// reference::choose_reference_solver on the output grid ("arkode" for a stiff oscillatory
/// model, else "cvode").
std::string resolve_reference_solver(const std::string& solver, const core::Model& model,
                                     const std::vector<double>& output_times);

/// The reference itself in one phrase: "cvode rtol 1e-12", or "exact solution (analytic, no
/// tolerance)" for the exact solution, whose run carries an rtol it never used.
std::string describe_reference_run(const reference::ReferenceRun& run);

/// "2.1e-10 (2 x distance to cvode rtol 1e-14, ...)": the estimate and its method, one line.
std::string describe_estimate(const ReferenceEstimate& estimate);

/// The largest |energy_balance| of a table (J) and the output time where it occurs (s); both
/// NaN when the table has no such column (a model that does not dissipate).
struct BalancePeak {
  double value = std::numeric_limits<double>::quiet_NaN();
  double time = std::numeric_limits<double>::quiet_NaN();
};
BalancePeak largest_energy_balance(const TrajectoryTable& table);

/// "largest |E - E0 + W_d - W_a - W_drive| 2.4e-05 J, 1.1 x the estimated error of its terms
/// (2.2e-05 J)", one line; empty when the model does not dissipate.
std::string describe_energy_balance(const ReferenceEstimate& estimate);

struct EstimateOptions {
  /// Use the model's exact solution when it has one (tests of the numerical estimate turn it
  /// off).
  bool use_exact_solution = true;
};

/// How many solves certified_reference makes (for a progress line, reference/solve_progress.hpp):
/// 4 for the exact solution (and its three checks), 2 for a numerical solver on a scene with an
/// exact solution (the run and the exact one), else 3 (the run and its two checks).
int reference_solve_count(const core::Model& model, const std::string& solver,
                          const EstimateOptions& estimate_options = {});

/// The size of a solution in `metric`, the yardstick of its error estimate: the metric of the
/// table's first row (held over every time) against a body at rest at the world origin with the
/// identity rotation, with the rotation part taken as π (the largest geodesic angle). For
/// "rotation+points": π + the largest distance of a tracked point from the origin at t0. For
/// the default metric, whose errors are fractions of each quantity's range: 1.
double solution_scale(const TrajectoryTable& table, const std::string& metric);

/// Runs the reference and its checks; throws like the solvers do (core::SolverError, also when
/// the estimate is NaN), and StudyRefused when a finite estimate exceeds
/// solution_scale(table, metric): an error larger than the scene itself certifies nothing
/// (e.g. a solution that diverges exponentially, spin_up_beam_6 under the coupled model,
/// where the solvers disagree by 1e34 m on a 10 m beam). Under the default metric the guard is
/// absolute (ReferenceEstimate::absolute_value against solution_scale(table,
/// "rotation+points")): a fraction of the reference's own range cannot see a solution that
/// grows without bound (spin_up_beam_6's 1e34 m are 1.9e-7 of its range).
CertifiedReference certified_reference(const core::Model& model,
                                       const std::vector<double>& output_times,
                                       const std::string& solver,
                                       const reference::SolverOptions& options,
                                       const std::string& metric,
                                       const EstimateOptions& estimate_options = {});

/// The estimate of an existing run (its table) against the model and output times it was
/// computed on.
ReferenceEstimate estimate_error(const core::Model& model, const std::vector<double>& output_times,
                                 const reference::ReferenceRun& run, const TrajectoryTable& table,
                                 const std::string& metric,
                                 const EstimateOptions& estimate_options = {});

}  // namespace flexref::trajectory
