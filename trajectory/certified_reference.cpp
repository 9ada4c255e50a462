#include "trajectory/certified_reference.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "reference/exact_solution.hpp"
#include "reference/method_choice.hpp"
#include "reference/solve_reference.hpp"
#include "trajectory/accuracy_check.hpp"
#include "trajectory/column_layout.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/study_refused.hpp"

namespace flexref::trajectory {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// A check is run this much tighter than the run.
constexpr double kTighterFactor = 100.0;
/// Twice the distance to a check at least twice as accurate bounds the error (see the header).
constexpr double kSafetyFactor = 2.0;

reference::SolverOptions tighter(const reference::SolverOptions& options) {
  reference::SolverOptions t = options;
  t.rtol = std::max(options.rtol / kTighterFactor, kTightestRtol);
  t.atol = options.atol < 0.0 ? -1.0 : std::max(options.atol / kTighterFactor, kTightestRtol);
  return t;
}

/// L∞ over the output times of the differences in the energy balance's terms, J; NaN when the
/// tables have no balance (a model that does not dissipate).
double energy_distance(const TrajectoryTable& a, const TrajectoryTable& b) {
  if (a.column("energy_balance") < 0) return std::numeric_limits<double>::quiet_NaN();
  double largest = 0.0;
  for (const char* name : {"energy", "dissipated_work", "applied_work"}) {
    const int ca = a.column(name);
    const int cb = b.column(name);
    if (ca < 0 || cb < 0) continue;
    for (std::size_t k = 0; k < a.rows.size() && k < b.rows.size(); ++k) {
      const double d = std::abs(a.rows[k][static_cast<std::size_t>(ca)] -
                                b.rows[k][static_cast<std::size_t>(cb)]);
      // A non-finite difference makes the distance infinite, never silently small.
      largest = std::isnan(d) ? kInf : std::max(largest, d);
    }
  }
  return largest;
}

EstimateCheck compare(const core::Model& model, const std::vector<double>& output_times,
                      const TrajectoryTable& table, const std::string& metric,
                      const std::string& role, const std::string& solver,
                      const reference::SolverOptions& options) {
  EstimateCheck c;
  c.role = role;
  c.solver = solver;
  c.rtol = solver == "exact" ? 0.0 : options.rtol;
  reference::ReferenceRun check;
  try {
    check = reference::solve_reference(solver, model, output_times, options);
  } catch (const core::SolverError& e) {
    // A check that fails (IDA at rtol 1e-14 on Andrews' squeezer: its corrector stops
    // converging) is no check; the run and the other checks stand, and the note says why.
    c.distance = std::numeric_limits<double>::quiet_NaN();
    c.energy_distance = std::numeric_limits<double>::quiet_NaN();
    c.note = std::string("the check failed: ") + e.what();
    return c;
  }
  c.method = check.method;
  c.steps = check.stats.steps;
  const TrajectoryTable check_table = tabulate(model, check.trajectory);
  const ComparisonReport report = compare_trajectories(table, check_table);
  c.distance = metric_value(report, metric);
  if (report.rotation_count + report.point_count > 0) {
    c.absolute_distance = metric_value(report, "rotation+points");
  }
  c.energy_distance = energy_distance(table, check_table);
  c.used = true;
  if (!(c.distance > 0.0)) {
    c.used = false;
    c.note = std::isnan(c.distance) ? "distance is not finite" : "distance exactly 0";
  }
  return c;
}

std::string number(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

std::string count_word(std::size_t n) {
  static const char* const kWords[] = {"no", "one", "two", "three", "four"};
  return n < std::size(kWords) ? kWords[n] : std::to_string(n);
}

}  // namespace

std::string cross_check_solver(const std::string& solver) {
  // CVODE and Odeint check each other: they share only the ODE form's right-hand side. IDA
  // (the DAE form's residual) is checked by CVODE. ARKODE is checked by Odeint, the other
  // order-8 explicit method (Boost's, with its own controller, norm and output): at rtol
  // 1e-12 it is more accurate than CVODE at 1e-14 on every exact scene (on the pendulum
  // CVODE's 1e-9 made ARKODE's estimate 140× its true error of 1e-11).
  if (solver == "cvode") return "odeint";
  if (solver == "arkode") return "odeint";
  return "cvode";
}

std::string resolve_reference_solver(const std::string& solver, const core::Model& model,
                                     const std::vector<double>& output_times) {
  if (solver != "auto") return solver;
  // classify_exact_solution does not look at flexibility (a free flexible body would pass as
  // torque-free): flexible models have no exact solution.
  if (!model.has_flexible_bodies() && !reference::classify_exact_solution(model).kind.empty()) {
    return "exact";
  }
  return reference::choose_reference_solver(model, reference::mean_output_spacing(output_times))
      .solver;
}

ReferenceEstimate estimate_error(const core::Model& model, const std::vector<double>& output_times,
                                 const reference::ReferenceRun& run, const TrajectoryTable& table,
                                 const std::string& metric,
                                 const EstimateOptions& estimate_options) {
  ReferenceEstimate e;
  e.metric = metric;
  if (run.solver == "exact") {
    // Three independent numerical solutions at tight tolerance; the smallest distance bounds
    // the exact solution's error plus the closest numerical one's.
    e.exact = true;
    reference::SolverOptions tightest;
    tightest.rtol = kTightestRtol;
    tightest.progress = run.options.progress;
    reference::SolverOptions cvode_options = tightest;
    cvode_options.rtol = 1e-13;
    e.checks.push_back(compare(model, output_times, table, metric, "other", "arkode", tightest));
    e.checks.push_back(compare(model, output_times, table, metric, "other", "odeint", tightest));
    e.checks.push_back(
        compare(model, output_times, table, metric, "other", "cvode", cvode_options));
    e.value = kInf;
    const EstimateCheck* closest = nullptr;
    std::string checked;
    for (const EstimateCheck& c : e.checks) {
      checked += (checked.empty() ? "" : ", ") + c.solver + " rtol " + number(c.rtol) +
                 (c.used ? "" : " (not used: " + c.note + ")");
      if (c.used && c.distance < e.value) {
        e.value = c.distance;
        closest = &c;
      }
    }
    e.absolute_value = closest == nullptr ? kInf : closest->absolute_distance;
    // Say what was computed: which solutions, which one gave the value.
    e.method = closest == nullptr
                   ? "none: no independent numerical solution is a usable check (" + checked + ")"
                   : "smallest distance to " + count_word(e.checks.size()) +
                         " independent numerical solutions (" + checked + "), to " +
                         closest->solver + " rtol " + number(closest->rtol) +
                         ": bounds the exact solution's error plus that solution's";
    return e;
  }

  const bool has_exact =
      !reference::classify_exact_solution(model).kind.empty() && !model.has_flexible_bodies();
  if (has_exact && estimate_options.use_exact_solution) {
    reference::SolverOptions exact_options;
    exact_options.progress = run.options.progress;
    EstimateCheck c = compare(model, output_times, table, metric, "exact", "exact", exact_options);
    e.value = c.used ? c.distance : kInf;
    e.absolute_value = c.used ? c.absolute_distance : kInf;
    e.checks.push_back(c);
    e.method =
        "distance to the exact solution (the run's true error, up to the exact "
        "solution's own, <= 1e-13)";
    return e;
  }

  const reference::SolverOptions tight = tighter(run.options);
  EstimateCheck same = compare(model, output_times, table, metric, "tighter", run.solver, tight);
  if (same.used && !(tight.rtol < run.options.rtol)) {
    same.used = false;
    same.note = "no tighter tolerance than 1e-14";
  } else if (same.used && same.steps == run.stats.steps) {
    same.used = false;
    same.note = "same number of steps as the run: not a different solution";
  }
  e.checks.push_back(same);
  e.checks.push_back(
      compare(model, output_times, table, metric, "other", cross_check_solver(run.solver), tight));
  double largest = 0.0;
  double largest_absolute = 0.0;
  std::string used;
  int used_count = 0;
  for (const EstimateCheck& c : e.checks) {
    if (!c.used) continue;
    largest = std::max(largest, c.distance);
    // NaN (nothing absolute measured) stays NaN: the guard then has nothing to hold.
    largest_absolute = std::isnan(c.absolute_distance)
                           ? c.absolute_distance
                           : std::max(largest_absolute, c.absolute_distance);
    used += (used.empty() ? "" : " and ") + c.solver + " rtol " + number(c.rtol);
    ++used_count;
  }
  e.value = used.empty() ? kInf : kSafetyFactor * largest;
  e.absolute_value = used.empty() ? kInf : kSafetyFactor * largest_absolute;
  const BalancePeak peak = largest_energy_balance(table);
  e.energy_balance = peak.value;
  e.energy_balance_time = peak.time;
  if (!std::isnan(e.energy_balance)) {
    double energy = 0.0;
    for (const EstimateCheck& c : e.checks) {
      if (c.used) energy = std::max(energy, c.energy_distance);
    }
    e.energy_estimate = used.empty() ? kInf : kSafetyFactor * energy;
  }
  // The checks' tolerance is 100x the run's, clamped at kTightestRtol: say the factor it is.
  const std::string tighter_text = number(run.options.rtol / tight.rtol) +
                                   "x tighter than the run's rtol " + number(run.options.rtol);
  e.method = used.empty()
                 ? "none: no check is a different, more accurate solution"
                 : (used_count > 1 ? "2 x the larger distance to " : "2 x the distance to ") +
                       used + " (" + (used_count > 1 ? "each " : "") + tighter_text +
                       ": twice the distance bounds the run's error when the check is at least "
                       "twice as accurate)";
  return e;
}

double solution_scale(const TrajectoryTable& table, const std::string& metric) {
  // Each quantity's error as a fraction of its whole range: the whole solution is 1.
  if (metric == kDefaultMetric) return 1.0;
  TrajectoryTable initial = table;
  TrajectoryTable rest = table;
  const ColumnLayout layout = ColumnLayout::parse(table.columns);
  for (std::size_t k = 0; k < table.rows.size(); ++k) {
    initial.rows[k] = table.rows.front();
    initial.rows[k][0] = table.rows[k][0];
    for (std::size_t c = 1; c < table.columns.size(); ++c) {
      const bool e0 = layout[c].kind == ColumnKind::rotation && layout[c].component == 0;
      rest.rows[k][c] = e0 ? 1.0 : 0.0;
    }
  }
  ComparisonReport report = compare_trajectories(initial, rest);
  report.max_rotation_linf = std::numbers::pi;
  return metric_value(report, metric);
}

CertifiedReference certified_reference(const core::Model& model,
                                       const std::vector<double>& output_times,
                                       const std::string& solver,
                                       const reference::SolverOptions& options,
                                       const std::string& metric,
                                       const EstimateOptions& estimate_options) {
  CertifiedReference result;
  result.run = reference::solve_reference(solver, model, output_times, options);
  result.table = tabulate(model, result.run.trajectory);
  // The checks report to the same progress line (solve_reference does not keep it in the run).
  reference::ReferenceRun reported = result.run;
  reported.options.progress = options.progress;
  result.estimate =
      estimate_error(model, output_times, reported, result.table, metric, estimate_options);
  const double estimate = result.estimate.estimate();
  if (std::isnan(estimate)) {
    throw core::SolverError(
        result.run.solver, output_times.back(), -1,
        "the error estimate is not a number (" + describe_estimate(result.estimate) + ")");
  }
  // +inf means no usable check (certifies nothing; the studies refuse it). A finite estimate
  // larger than the solution itself is refused here: under the default metric in absolute
  // terms, rad + m against π rad + the scene's extent at t0, since a fraction of the
  // reference's own range does not grow with a solution that diverges.
  const bool absolute = metric == kDefaultMetric;
  const std::string guard_metric = absolute ? "rotation+points" : metric;
  const double guarded = absolute ? result.estimate.absolute_value : estimate;
  const double scale = std::isnan(guarded) ? 0.0 : solution_scale(result.table, guard_metric);
  const bool beyond_range = absolute && std::isfinite(estimate) && estimate > 1.0;
  const bool beyond_size = std::isfinite(guarded) && scale > 0.0 && guarded > scale;
  if (beyond_range || beyond_size) {
    const std::string size =
        beyond_size ? (absolute ? ", " + number(guarded) + " in rotation+points (rad + m)," : "") +
                          std::string(" larger than the solution itself (") + number(scale) +
                          " in " + guard_metric + ": pi rad + the scene's extent at t0)"
                    : std::string(" larger than 1, each quantity's whole range");
    throw StudyRefused("the reference (" + result.run.solver + ") has the estimated error " +
                       describe_estimate(result.estimate) + " in " + metric + size +
                       ": it certifies nothing. The solvers disagree entirely, or the solution "
                       "diverges (a model without geometric stiffening spun above its first "
                       "frequency grows exponentially: docs/design/model.md)");
  }
  return result;
}

int reference_solve_count(const core::Model& model, const std::string& solver,
                          const EstimateOptions& estimate_options) {
  if (solver == "exact") return 4;  // the exact solution and three numerical checks
  const bool has_exact =
      !reference::classify_exact_solution(model).kind.empty() && !model.has_flexible_bodies();
  return has_exact && estimate_options.use_exact_solution ? 2 : 3;
}

std::string describe_reference_run(const reference::ReferenceRun& run) {
  if (run.solver == "exact") return "exact solution (analytic, no tolerance)";
  return run.solver + " rtol " + number(run.options.rtol);
}

BalancePeak largest_energy_balance(const TrajectoryTable& table) {
  BalancePeak peak;
  const int c = table.column("energy_balance");
  if (c < 0 || table.rows.empty()) return peak;
  const auto at = [](const std::vector<double>& row, int column) {
    return row[static_cast<std::size_t>(column)];
  };
  const int t = table.column("t");
  peak.value = 0.0;
  for (const auto& row : table.rows) {
    const double b = std::abs(at(row, c));
    // A non-finite balance is the peak: never reported as small.
    if (!(b <= peak.value)) {
      peak.value = std::isnan(b) ? kInf : b;
      peak.time = t < 0 ? peak.time : at(row, t);
      if (std::isinf(peak.value)) break;
    }
  }
  if (std::isnan(peak.time) && t >= 0) peak.time = at(table.rows.front(), t);
  return peak;
}

std::string describe_energy_balance(const ReferenceEstimate& e) {
  if (std::isnan(e.energy_balance)) return "";
  std::ostringstream out;
  out.precision(2);
  out << "largest |E - E0 + W_d - W_a - W_drive| " << e.energy_balance
      << " J at t = " << e.energy_balance_time << " s";
  if (std::isfinite(e.energy_estimate) && e.energy_estimate > 0.0) {
    out << ", " << e.energy_balance / e.energy_estimate << " x the estimated error of its terms ("
        << e.energy_estimate << " J)";
  } else if (!std::isnan(e.energy_estimate)) {
    out << " (the estimated error of its terms is " << e.energy_estimate << " J)";
  }
  return out.str();
}

std::string describe_estimate(const ReferenceEstimate& e) {
  std::ostringstream out;
  out.precision(3);
  out << e.value << " (" << e.method << ")";
  return out.str();
}

}  // namespace flexref::trajectory
