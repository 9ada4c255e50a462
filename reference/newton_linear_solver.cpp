/// \file newton_linear_solver.cpp
/// See newton_linear_solver.hpp.
#include "reference/newton_linear_solver.hpp"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <exception>
#include <new>

#include "reference/custom_linear_solver.hpp"
#include "reference/newton_matrix.hpp"

namespace flexref::reference {
namespace {

struct Content {
  explicit Content(const OdeForm& form) : solver(form) {}
  NewtonMatrixSolver solver;
  sunindextype last_flag = SUNLS_SUCCESS;
};

Content& content(SUNLinearSolver S) { return sundials::solver_content<Content>(S); }

int initialize(SUNLinearSolver S) {
  content(S).last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int setup(SUNLinearSolver S, SUNMatrix A) {
  Content& c = content(S);
  if (SUNMatGetID(A) != SUNMATRIX_DENSE || SM_ROWS_D(A) != c.solver.size() ||
      SM_COLUMNS_D(A) != c.solver.size()) {
    c.last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  c.last_flag = c.solver.factor(SM_DATA_D(A), static_cast<int>(SM_ROWS_D(A))) ? SUNLS_SUCCESS
                                                                              : SUNLS_LUFACT_FAIL;
  return static_cast<int>(c.last_flag);
}

int solve(SUNLinearSolver S, SUNMatrix /*A*/, N_Vector x, N_Vector b, realtype /*tol*/) {
  Content& c = content(S);
  N_VScale(1.0, b, x);
  c.solver.solve(N_VGetArrayPointer(x));
  c.last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

sunindextype last_flag(SUNLinearSolver S) { return content(S).last_flag; }

}  // namespace

SUNLinearSolver make_newton_linear_solver(const OdeForm& form, SUNContext context) {
  return sundials::make_custom_solver<Content>(context, {initialize, setup, solve, last_flag},
                                               form);
}

}  // namespace flexref::reference
