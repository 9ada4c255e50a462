#pragma once
/// \file solve_reference.hpp
/// Dispatch by solver name: "ida", "cvode", "arkode", "odeint", "exact".
#include <string>
#include <vector>

#include "reference/reference_solver.hpp"

namespace flexref::reference {

/// The solver names `flexref reference --solver` accepts.
std::vector<std::string> reference_solver_names();

/// Throws core::SolverError(solver, t, −1, why) at the first output time t whose state, energy
/// (kinetic + potential) or dissipated work is not finite, or when the trajectory has not one
/// state per output time: no reference with an inf or a NaN reaches a file or a study.
void check_finite(const ReferenceRun& run, const core::Model& model);

/// Throws core::SolverError(solver, t, −1, why) at the first output time where a joint row — a
/// row set aside as redundant included — is violated beyond the bound the run's tolerances imply
/// (core/joint_check.hpp): no reference off its joints reaches a file or a study.
void check_joints(const ReferenceRun& run, const core::Model& model);

/// Runs the named solver, check_finite and check_joints on its result; throws
/// std::invalid_argument for an unknown name, core::SolverError when the solver fails, its result
/// is not finite or off its joints.
ReferenceRun solve_reference(const std::string& solver, const core::Model& model,
                             const std::vector<double>& output_times, const SolverOptions& options);

}  // namespace flexref::reference
