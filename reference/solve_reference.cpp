#include "reference/solve_reference.hpp"

#include <stdexcept>

#include "reference/exact_solution.hpp"

namespace flexref::reference {

std::vector<std::string> reference_solver_names() {
  return {"ida", "cvode", "arkode", "odeint", "exact"};
}

ReferenceRun solve_reference(const std::string& solver, const core::Model& model,
                             const std::vector<double>& output_times,
                             const SolverOptions& options) {
  if (solver == "ida") return solve_ida(model, output_times, options);
  if (solver == "cvode") return solve_cvode(model, output_times, options);
  if (solver == "arkode") return solve_arkode(model, output_times, options);
  if (solver == "odeint") return solve_odeint(model, output_times, options);
  if (solver == "exact") return solve_exact(model, output_times);
  throw std::invalid_argument("unknown reference solver '" + solver +
                              "' (ida, cvode, arkode, odeint, exact)");
}

}  // namespace flexref::reference
