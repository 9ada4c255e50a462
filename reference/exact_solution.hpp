#pragma once
/// \file exact_solution.hpp
/// Analytic references for the scenes that have one (docs/design/schemes.md, "Exact solutions"):
/// a single free body without loads (torque-free, Jacobi elliptic functions), a single
/// symmetric pivot body under gravity with its centre of mass on the symmetry axis (Lagrange
/// top), and a single pivot body under gravity released at rest swinging about a principal
/// axis (compound pendulum).
#include <string>
#include <vector>

#include "core/model.hpp"
#include "reference/reference_solver.hpp"

namespace flexref::reference {

/// Which exact solution applies ("torque_free", "heavy_top", "pendulum"), or why none does.
struct ExactSolutionKind {
  std::string kind;    ///< empty when there is none
  std::string reason;  ///< why not, when kind is empty
};

ExactSolutionKind classify_exact_solution(const core::Model& model);

/// Evaluates the exact solution at the output times; throws std::invalid_argument (with the
/// reason) when the model has none.
ReferenceRun solve_exact(const core::Model& model, const std::vector<double>& output_times);

}  // namespace flexref::reference
