#pragma once
/// \file high_precision_reference.hpp
/// References beyond double precision (docs/precision.md): core::ModelTpl<S>
/// (precision/ode_system.hpp) integrated in extended or quad precision by Boost.Odeint's
/// Bulirsch–Stoer extrapolation (controlled, stepping exactly onto every output time and load
/// switch, and locating every contact switch to the working precision), with its error
/// estimated in the same precision.
#include <string>
#include <vector>

#include "core/model.hpp"
#include "precision/precision.hpp"
#include "precision/reference_budget.hpp"
#include "reference/solve_progress.hpp"
#include "scene/scene_spec.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {

/// The default relative tolerance of a precision: 1e-12 (double), 1e-16 (extended), 1e-28
/// (quad): a hundred times above the tightest the estimate's check can reach (rtol/100 must
/// stay ≥ ~100 ε of the precision, where extrapolation still converges).
double default_rtol(Precision precision);
/// The smallest rtol accepted for a precision (1e-13, 1e-17, 1e-30); throws nothing.
double smallest_rtol(Precision precision);

/// A switch located by an extended/quad run (precision/switched_integration.hpp): a contact
/// pair's onset (gap < 0 from then on) or release, or its penalty law's clamp starting or
/// stopping to act.
struct HighPrecisionEvent {
  std::string time;  ///< printed with significant_digits(precision) digits
  int pair = 0;      ///< contact pair, in the scene's order (over all [[contact]] tables)
  std::string kind;  ///< "onset", "release", "clamp" or "unclamp"
  std::vector<std::string> row;  ///< the columns after `t` at the event, as `text`
};

struct HighPrecisionRun {
  Precision precision = Precision::kQuad;
  double rtol = 0.0;
  std::string method;                ///< "bulirsch-stoer (odeint), long double" …
  std::vector<std::string> columns;  ///< trajectory_columns order ("t" first)
  /// Per output time: every value after `t`, printed with significant_digits(precision)
  /// digits (they round-trip: distances are computed from them in the run's precision).
  std::vector<std::vector<std::string>> text;
  trajectory::TrajectoryTable table;       ///< the same values rounded to double
  std::vector<HighPrecisionEvent> events;  ///< every located switch, in time order
  long steps = 0;
  long evaluations = 0;
  double cpu_seconds = 0.0;
};

/// Builds the extended/quad model of the scene in double: throws std::invalid_argument with
/// what scene::build_model refuses (the model carries every scene build_model builds,
/// docs/precision.md); returns normally otherwise.
void check_supported(const scene::SceneSpec& spec,
                     core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled);

/// Solves the scene at output_times in `precision` (kExtended or kQuad) with rtol (= atol) by
/// core::ModelTpl<S> (precision/ode_system.hpp; its flexible bodies coupled or LTE, as
/// `formulation` says). Throws std::invalid_argument for a scene build_model refuses or an rtol out
/// of range, core::SolverError when the integration fails or leaves a non-finite value. `progress`
/// (may be null) follows the solve (reference/solve_progress.hpp).
HighPrecisionRun solve_high_precision(
    const scene::SceneSpec& spec, const std::vector<double>& output_times, Precision precision,
    double rtol, core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled,
    reference::SolveProgress* progress = nullptr);

/// metric(a, b) computed in the runs' precision (both of the same precision and columns), b the
/// reference whose ranges scale the default metric: "relative" (trajectory::kDefaultMetric),
/// "rotation+points" (L∞ geodesic angle + L∞ tracked-point distance, max over bodies and
/// points), "rotation" or "points".
double distance(const HighPrecisionRun& a, const HighPrecisionRun& b, const std::string& metric);

/// The run and its error estimate as a trajectory::CertifiedReference: 2 × the distance to a run
/// of the same precision at rtol/100 (a different step sequence; the checks are recorded).
/// budget_seconds > 0 bounds the wall time of the whole (reference_budget.hpp): the runs
/// project their cost from the simulated time reached and throw BudgetExceeded when it is over
/// (0: no bound). `progress` (may be null) follows its solves: the run and its check (2; 3 when
/// the check is repeated with shorter steps).
trajectory::CertifiedReference certified_high_precision_reference(
    const scene::SceneSpec& spec, const std::vector<double>& output_times, Precision precision,
    double rtol, const std::string& metric, HighPrecisionRun* run_out = nullptr,
    core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled,
    double budget_seconds = 0.0, reference::SolveProgress* progress = nullptr);

/// The CSV text of a run: header, then rows with `t` in 17 digits and the values as printed.
std::string high_precision_csv(const HighPrecisionRun& run);

}  // namespace flexref::precision
