#pragma once
/// \file ode_jacobian.hpp
/// The hook for a user-supplied Jacobian J = ∂f/∂y of the ODE form's right-hand side
/// (reference/ode_form.hpp), for models whose difference-quotient Jacobian is too costly (many
/// modes) or too inexact. Without one (SolverOptions::jacobian == nullptr) the implicit
/// references use the StructuredJacobian (reference/structured_jacobian.hpp) with the structured
/// Newton solve for models with flexible bodies, and their own difference quotients with a dense
/// LU for rigid ones (choose_newton_jacobian, reference/method_choice.hpp).
///
/// With one, the implicit SUNDIALS references use it with a dense LU:
///  - CVODE (BDF, or Adams with Newton iteration): CVodeSetJacFn, SUNDIALS forms I − γJ; ARKODE's
///    ESDIRK likewise (ARKStepSetJacFn);
///  - IDA on the DAE form (reference/dae_form.hpp, same layout of y): the iteration matrix
///      ∂F/∂y + c_j ∂F/∂y' = P (c_j I − J),   P = ∂F/∂y' = blockdiag(I, M(θ̂, q))
///    (DaeForm::mass_rows), exact in the kinematic rows and, in the dynamics rows
///    F_d = M (v̇ − f_d) + (M f_d − Q), up to (∂M/∂y)(v̇ − f_d), which vanishes on consistent
///    values: Newton converges as with the exact matrix near the solution.
/// ARKODE's explicit ERK and Odeint need no Jacobian.
#include <Eigen/Core>

#include "core/force_element.hpp"
#include "reference/ode_form.hpp"

namespace flexref::reference {

class OdeJacobian {
 public:
  virtual ~OdeJacobian() = default;
  /// Writes J = ∂f/∂y at (context, y) into `jacobian` (form.size() square, every entry:
  /// it is not cleared before the call); fy = f(context, y) is given. Must not allocate.
  virtual void evaluate(const OdeForm& form, const core::LoadContext& context, const double* y,
                        const double* fy, Eigen::Ref<Eigen::MatrixXd> jacobian,
                        OdeForm::Scratch& scratch) const = 0;
};

}  // namespace flexref::reference
