#pragma once
/// \file custom_linear_solver.hpp
/// SUNDIALS' custom direct linear solver — a SUNLinearSolver whose content and operations are
/// flexref's (the structured Newton solves of CVODE and IDA, IDA's works' completion) — made and
/// freed in one place. Internal: SUNDIALS types.
#include <sundials/sundials_linearsolver.h>

#include <new>
#include <utility>

namespace flexref::reference::sundials {

/// The Content a custom solver made by make_custom_solver<Content> holds.
template <typename Content>
Content& solver_content(SUNLinearSolver S) {
  return *static_cast<Content*>(S->content);
}

/// The operations of a custom solver besides its type, its id and `free`.
struct CustomSolverOps {
  int (*initialize)(SUNLinearSolver);
  int (*setup)(SUNLinearSolver, SUNMatrix);
  int (*solve)(SUNLinearSolver, SUNMatrix, N_Vector, N_Vector, realtype);
  sunindextype (*last_flag)(SUNLinearSolver);
};

/// A direct custom solver with a Content{args...} on the heap, freed (with the Content) by its
/// `free`. Throws std::bad_alloc, or what Content's construction throws (nothing leaks).
template <typename Content, typename... Args>
SUNLinearSolver make_custom_solver(SUNContext context, const CustomSolverOps& ops, Args&&... args) {
  SUNLinearSolver S = SUNLinSolNewEmpty(context);
  if (S == nullptr) throw std::bad_alloc();
  try {
    S->content = new Content{std::forward<Args>(args)...};
  } catch (...) {
    SUNLinSolFreeEmpty(S);
    throw;
  }
  S->ops->gettype = [](SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; };
  S->ops->getid = [](SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; };
  S->ops->initialize = ops.initialize;
  S->ops->setup = ops.setup;
  S->ops->solve = ops.solve;
  S->ops->lastflag = ops.last_flag;
  S->ops->free = [](SUNLinearSolver solver) {
    if (solver == nullptr) return static_cast<int>(SUNLS_SUCCESS);
    delete static_cast<Content*>(solver->content);
    solver->content = nullptr;
    SUNLinSolFreeEmpty(solver);
    return static_cast<int>(SUNLS_SUCCESS);
  };
  return S;
}

}  // namespace flexref::reference::sundials
