#pragma once
/// \file ida_callbacks.hpp
/// IDA's user data and the callbacks IDA calls with it (reference/ida_solver.cpp drives IDA on the
/// DAE form): the error weights, the switching and singular-configuration root functions, the
/// residual and the Newton matrices (the user's ODE Jacobian, the structured path of flexible
/// models, the coloured difference quotients of ideal joints). Internal: SUNDIALS types.
#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "reference/dae_coloured_jacobian.hpp"
#include "reference/dae_form.hpp"
#include "reference/error_weights.hpp"
#include "reference/ida_newton_solver.hpp"
#include "reference/ida_work_completion.hpp"
#include "reference/integral_weights.hpp"
#include "reference/method_choice.hpp"
#include "reference/ode_form.hpp"
#include "reference/ode_jacobian.hpp"
#include "reference/reference_solver.hpp"
#include "reference/step_clock.hpp"
#include "reference/structured_jacobian.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_segment_driver.hpp"

namespace flexref::reference::ida {

namespace sun = sundials;

/// Absolute tolerance of the joints' multipliers relative to their largest initial size (see
/// start_segment): large enough that they never decide the Newton convergence test.
constexpr double kMultiplierTolerance = 1e3;

/// IDA's smallest step after a fallback, in ulp of the time (continue_without_share).
constexpr double kMinStepUlps = 8.0;

struct IdaData : sun::CallbackRecord {
  const DaeForm* form = nullptr;
  DaeForm::Scratch scratch;
  double t_segment = 0.0;
  /// For SolverOptions::jacobian: the ODE form (same layout), its scratch and J, P.
  const OdeJacobian* jacobian = nullptr;
  const OdeForm* ode = nullptr;
  OdeForm::Scratch ode_scratch;
  Eigen::MatrixXd ode_jacobian;
  Eigen::MatrixXd mass;
  Eigen::VectorXd f;
  /// For NewtonJacobian::kStructured: the structured Jacobian and Newton system.
  const StructuredJacobian* structured = nullptr;
  StructuredJacobian::Scratch structured_scratch;
  IdaNewtonSystem* newton = nullptr;
  /// For NewtonJacobian::kColoured: the pattern and groups, KLU (re-analysed when the pattern
  /// changes) and the residuals its difference quotients cost (IDA does not count them).
  DaeColouredJacobian* coloured = nullptr;
  SUNLinearSolver klu = nullptr;
  long coloured_residuals = 0;
  /// With tracked works: their corrections completed with the state's (ida_work_completion.hpp).
  IdaWorkCompletion* completion = nullptr;
  /// Ideal joints: the rows in force and the last accepted state's rows (core/
  /// constraint_tracker.hpp), moved by the root function after every step
  /// (Model::advance_tracker: the singular-configuration tests IDA's residual never makes).
  core::ConstraintTracker tracker;
  /// The callback whose exception failed the solve (failure_message).
  const char* failed_callback = "residual";
  /// IDA's memory, to read its accepted steps from (error_weights).
  void* ida = nullptr;
};

/// Adds IDA's accepted steps since the last call to the clock.
void record_steps(void* ida, StepClock& clock);
/// IDAEwtFn (error_weights.hpp; records the step just taken on the clock).
int error_weights(N_Vector y, N_Vector ewt, void* user_data);
/// The rotation blocks of the DAE form's bodies (θ and ω̄ offsets in y).
std::vector<RotationBlock> rotation_blocks(const DaeForm& form);
/// IDARootFn: the model's switching functions, then the singular-configuration tracker's entry.
int switching(sunrealtype t, N_Vector y, N_Vector yp, sunrealtype* g, void* user_data);
/// IDAResFn: F(t, y, y') of the DAE form.
int residual(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* user_data);
/// IDALsJacFn from the user's ODE Jacobian.
int jacobian(sunrealtype t, sunrealtype c_j, N_Vector y, N_Vector yp, N_Vector r, SUNMatrix G,
             void* user_data, N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);
/// IDALsJacFn of the structured path (flexible models).
int structured_jacobian(sunrealtype t, sunrealtype c_j, N_Vector y, N_Vector yp, N_Vector r,
                        SUNMatrix G, void* user_data, N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);
/// IDALsJacFn of the sparse path (ideal joints): coloured difference quotients into KLU's matrix.
int coloured_jacobian(sunrealtype t, sunrealtype c_j, N_Vector y, N_Vector yp, N_Vector r,
                      SUNMatrix G, void* user_data, N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);

}  // namespace flexref::reference::ida
