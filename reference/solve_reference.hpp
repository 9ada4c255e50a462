#pragma once
/// \file solve_reference.hpp
/// Dispatch by solver name: "ida", "cvode", "arkode", "odeint", "exact".
#include <string>
#include <vector>

#include "reference/reference_solver.hpp"

namespace flexref::reference {

/// The solver names `flexref reference --solver` accepts.
std::vector<std::string> reference_solver_names();

/// Runs the named solver; throws std::invalid_argument for an unknown name.
ReferenceRun solve_reference(const std::string& solver, const core::Model& model,
                             const std::vector<double>& output_times, const SolverOptions& options);

}  // namespace flexref::reference
