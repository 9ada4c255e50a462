#include "studies/certified_reference.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "reference/exact_solution.hpp"
#include "reference/solve_reference.hpp"
#include "studies/error_metrics.hpp"
#include "studies/study_refused.hpp"

namespace flexref::studies {
namespace {

std::string number(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

}  // namespace

std::string cross_check_solver(const std::string& solver) {
  // CVODE and Odeint check each other: they share only the ODE form's right-hand side, and
  // both reach ~1e-8 on the book toss where IDA (BDF on the index-2 DAE) stops near 1e-5.
  if (solver == "cvode") return "odeint";
  return "cvode";
}

std::string resolve_reference_solver(const std::string& solver, const core::Model& model) {
  if (solver != "auto") return solver;
  return reference::classify_exact_solution(model).kind.empty() ? "cvode" : "exact";
}

void add_reference(StudyRecord& record, const CertifiedReference& reference) {
  const ReferenceEstimate& e = reference.estimate;
  record.table("reference")
      .set("solver", reference.run.solver)
      .set("rtol", reference.run.options.rtol)
      .set("estimated_error", e.estimate())
      .set("metric", e.metric)
      .set("tighter_solver", e.tighter_solver)
      .set("tighter_rtol", e.tighter_rtol)
      .set("vs_tighter", e.vs_tighter)
      .set("other_solver", e.other_solver)
      .set("other_rtol", e.other_rtol)
      .set("vs_other_solver", e.vs_other_solver);
}

double solution_scale(const TrajectoryTable& table, const std::string& metric) {
  TrajectoryTable initial = table;
  TrajectoryTable rest = table;
  for (std::size_t k = 0; k < table.rows.size(); ++k) {
    initial.rows[k] = table.rows.front();
    initial.rows[k][0] = table.rows[k][0];
    for (std::size_t c = 1; c < table.columns.size(); ++c) {
      rest.rows[k][c] = table.columns[c].ends_with(".e0") ? 1.0 : 0.0;
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
                                       const std::string& metric) {
  CertifiedReference result;
  result.run = reference::solve_reference(solver, model, output_times, options);
  result.table = tabulate(model, result.run.trajectory);
  result.estimate.metric = metric;

  // Rerun 100× tighter (relative tolerances below ~1e-14 are round-off limited: clamp there).
  reference::SolverOptions tighter = options;
  tighter.rtol = std::max(options.rtol / 100.0, 1e-14);
  tighter.atol = options.atol < 0.0 ? -1.0 : std::max(options.atol / 100.0, 1e-14);
  reference::SolverOptions other_options = options;
  std::string tight_solver = solver;
  if (solver == "exact") {
    result.estimate.exact = true;
    tight_solver = "odeint";
    tighter = reference::SolverOptions{};
    tighter.rtol = 1e-13;
    other_options = reference::SolverOptions{};
    other_options.rtol = 1e-12;
  }
  const reference::ReferenceRun tight_run =
      reference::solve_reference(tight_solver, model, output_times, tighter);
  result.estimate.tighter_solver = tight_solver;
  result.estimate.tighter_rtol = tighter.rtol;
  result.estimate.vs_tighter = metric_value(
      compare_trajectories(result.table, tabulate(model, tight_run.trajectory)), metric);

  const std::string other = cross_check_solver(solver);
  const reference::ReferenceRun other_run =
      reference::solve_reference(other, model, output_times, other_options);
  result.estimate.other_solver = other;
  result.estimate.other_rtol = other_options.rtol;
  result.estimate.vs_other_solver = metric_value(
      compare_trajectories(result.table, tabulate(model, other_run.trajectory)), metric);

  const double estimate = result.estimate.estimate();
  const double t_end = output_times.back();
  if (!std::isfinite(estimate)) {
    throw core::SolverError(result.run.solver, t_end, -1,
                            "the error estimate is not finite (vs " + tight_solver + ": " +
                                number(result.estimate.vs_tighter) + ", vs " + other + ": " +
                                number(result.estimate.vs_other_solver) + ")");
  }
  const double scale = solution_scale(result.table, metric);
  if (scale > 0.0 && estimate > scale) {
    throw StudyRefused(
        "the reference (" + result.run.solver + ") has the estimated error " + number(estimate) +
        " (" + metric + "; vs " + tight_solver + " " + number(result.estimate.vs_tighter) +
        ", vs " + other + " " + number(result.estimate.vs_other_solver) +
        "), larger than the solution itself (" + number(scale) +
        " in that metric: pi rad + the scene's extent at t0): it certifies nothing. The solvers "
        "disagree "
        "entirely, or the solution diverges (a model without geometric stiffening spun above "
        "its first frequency grows exponentially: docs/design/model.md)");
  }
  return result;
}

}  // namespace flexref::studies
