#include "studies/certified_reference.hpp"

#include <algorithm>
#include <sstream>

#include "reference/exact_solution.hpp"
#include "reference/solve_reference.hpp"
#include "studies/error_metrics.hpp"

namespace flexref::studies {

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
  return result;
}

}  // namespace flexref::studies
