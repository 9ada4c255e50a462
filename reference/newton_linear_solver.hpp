#pragma once
/// \file newton_linear_solver.hpp
/// A SUNDIALS linear solver (SUNLinearSolver, direct, matrix-based with a dense SUNMatrix) that
/// solves CVODE's Newton systems with reference/newton_matrix.hpp instead of a dense LU: CVODE
/// forms A = I − γJ in the dense matrix from the Jacobian (reference/structured_jacobian.hpp, or
/// its own difference quotients), calls setup(A) — here the reduction to the velocities and the LU
/// of the (Σ 6 + n)² reduced matrix — and solve(A, x, b) per Newton iteration.
///
/// Use in a CVODE driver on the ODE form:
///
///     const sun::Matrix J = sun::make_dense_matrix(n, context);  // CVODE forms A in it
///     SUNLinearSolver LS = make_newton_linear_solver(form, context);  // SUNLinSolFree(LS) after
///     CVodeSetLinearSolver(cvode, LS, J.get());
///     CVodeSetJacFn(cvode, jac);  // StructuredJacobian::evaluate, see structured_jacobian.hpp
///
/// setup returns SUNLS_LUFACT_FAIL (recoverable: CVODE retries with a fresh Jacobian or a
/// smaller step) when A lacks the ODE form's kinematic pattern or the reduced matrix is
/// singular. Neither setup nor solve allocates.
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include "reference/ode_form.hpp"

namespace flexref::reference {

/// The form must outlive the solver; free it with SUNLinSolFree.
SUNLinearSolver make_newton_linear_solver(const OdeForm& form, SUNContext context);

}  // namespace flexref::reference
