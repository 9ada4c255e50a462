#pragma once
/// \file arkode_esdirk_solver.hpp
/// ARKODE's implicit reference: ARKStep with the ESDIRK5(4)7L[2]SA table on the ODE form
/// (arkode_esdirk_solver.cpp), the method `--solver arkode` runs with ArkodeMethod::kEsdirk
/// (by default on stiff oscillatory scenes, reference/method_choice.hpp).
#include <vector>

#include "core/model.hpp"
#include "reference/reference_solver.hpp"

namespace flexref::reference {

/// run.method = "esdirk547l2sa-7-4-5"; run.method_reason "chosen with --method" (solve_arkode
/// replaces it with its automatic choice's reason). Throws core::SolverError like the others.
ReferenceRun solve_arkode_esdirk(const core::Model& model, const std::vector<double>& output_times,
                                 const SolverOptions& options);

}  // namespace flexref::reference
