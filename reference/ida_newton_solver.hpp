#pragma once
/// \file ida_newton_solver.hpp
/// IDA's Newton systems on the DAE form (reference/dae_form.hpp) solved through the structure
/// of the ODE form's Newton matrix (reference/newton_matrix.hpp), for flexible models.
///
/// IDA's iteration matrix is G = ∂F/∂y + c_j ∂F/∂y' ≈ P (c_j I − J) = c_j P (I − γ J), γ = 1/c_j,
/// with J = ∂f/∂y of the ODE form (reference/structured_jacobian.hpp; the same layout of y) and
/// P = ∂F/∂y' = blockdiag(I, M): exact in the kinematic rows and, in the dynamics rows, up to
/// (∂M/∂y)(v̇ − f), which vanishes on consistent values (reference/ode_jacobian.hpp). So
///
///     G⁻¹ b = γ (I − γ J)⁻¹ P⁻¹ b,   P⁻¹ b: b_V ← M_VV⁻¹ b_V (the velocity rows), rest unchanged,
///
/// with (I − γJ) solved by NewtonMatrixSolver (positions eliminated through the kinematic rows,
/// LU of the (Σ 6 + n)² velocity system) and M_VV by an LU of the same size — instead of IDA's
/// dense LU of the (13 + 2n)² matrix G formed by a dense product.
///
/// IDA sees a SUNMatrix that holds A = I − γJ (setup_matrix() writes it from J at the current
/// c_j, and factors M_VV); it only passes that matrix from its Jacobian function to the linear
/// solver's setup and solve, so what it holds is the solver's business. The linear solver
/// (make_ida_newton_linear_solver) factors A in setup and applies the formula above in solve.
/// Nothing allocates after construction.
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

#include "reference/dae_form.hpp"
#include "reference/newton_matrix.hpp"
#include "reference/ode_form.hpp"

namespace flexref::reference {

class IdaNewtonSystem {
 public:
  /// The forms must outlive the system and have the same layout (DaeForm's is OdeForm's).
  IdaNewtonSystem(const DaeForm& dae, const OdeForm& ode);

  /// Turns J (column-major, size()², leading dimension size()) into A = I − J/c_j in place and
  /// factors the velocity block of P = ∂F/∂y' at (context, y). Returns false when M_VV is not
  /// finite.
  bool setup_matrix(const core::LoadContext& context, const double* y, double c_j, double* J,
                    DaeForm::Scratch& scratch);
  /// Factors A (as written by setup_matrix); false as NewtonMatrixSolver::factor.
  bool factor(const double* A) { return newton_.factor(A, size()); }
  /// x ← G⁻¹ x with the last setup_matrix and factor.
  void solve(double* x) const;

  int size() const { return newton_.size(); }

 private:
  NewtonMatrixSolver newton_;
  const DaeForm* dae_;
  std::vector<int> velocity_;  ///< the velocity rows of y (v, ω̄, q̇_f of every body)
  Eigen::MatrixXd mass_;       ///< P, size()²
  Eigen::MatrixXd mass_VV_;
  Eigen::PartialPivLU<Eigen::MatrixXd> mass_lu_;
  mutable Eigen::VectorXd b_V_, x_V_;
  double c_j_ = 1.0;
};

/// A direct SUNLinearSolver around `system` (not owned; it must outlive the solver, which is
/// freed with SUNLinSolFree). setup: IdaNewtonSystem::factor (SUNLS_LUFACT_FAIL, recoverable,
/// when it fails); solve: IdaNewtonSystem::solve.
SUNLinearSolver make_ida_newton_linear_solver(IdaNewtonSystem& system, SUNContext context);

}  // namespace flexref::reference
