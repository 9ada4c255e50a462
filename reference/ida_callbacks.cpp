#include "reference/ida_callbacks.hpp"

namespace flexref::reference::ida {

namespace {

/// A callback's return for its `count` values: 0 where all are finite, else 1 (recoverable: a
/// trial step may have reached a singular load, a charge on the wall; IDA retries with a smaller
/// step and gives up with its own message if that does not help), the time kept for that message.
int finite_or_retry(IdaData& d, sunrealtype t, const double* values, long count) {
  if (sun::all_finite(values, count)) return 0;
  d.last_nonfinite_time = t;
  return 1;
}

}  // namespace

void record_steps(void* ida, StepClock& clock) {
  long steps = 0;
  double last_step = 0.0, t = 0.0;
  sun::check(IDAGetNumSteps(ida, &steps), "IDAGetNumSteps");
  if (steps == 0) return;
  sun::check(IDAGetLastStep(ida, &last_step), "IDAGetLastStep");
  sun::check(IDAGetCurrentTime(ida, &t), "IDAGetCurrentTime");
  clock.record(steps, last_step, t);
}

/// IDAEwtFn: IDA calls it before every step (error_weights.hpp); it also records the step just
/// taken on the clock. Allocates nothing.
int error_weights(N_Vector y, N_Vector ewt, void* user_data) {
  auto& d = *static_cast<IdaData*>(user_data);
  try {
    record_steps(d.ida, *d.clock);
    sun::step_error_weights(d, y, ewt);
  } catch (...) {
    d.callback_error = std::current_exception();
    d.failed_callback = "error weights";
    return -1;
  }
  return 0;
}

/// The rotation blocks of the DAE form's bodies (θ and ω̄ offsets in y).
std::vector<RotationBlock> rotation_blocks(const DaeForm& form) {
  std::vector<RotationBlock> blocks;
  for (const DaeForm::Block& k : form.blocks()) {
    if (k.theta >= 0) blocks.push_back({k.theta, k.w, k.p, k.v});
  }
  return blocks;
}

/// The model's switching functions at (t, y), then with ideal joints the singular-configuration
/// tracker: IDA evaluates the root functions after every step (and at the outputs and event
/// searches between), and its GGL residual never factors J M⁻¹ Jᵀ, so this is where a dead point
/// stepped over is seen (docs/joints.md): the tracker moves to each such state. Its own entry is 1
/// while the tracker's rows are the DAE's and −1 once it chose others (the DAE's became dependent
/// among themselves, or ill conditioned: core::choose_rows): a root where the driver switches the
/// DAE's rows. Allocates nothing but on a row change.
int switching(sunrealtype t, N_Vector y, N_Vector /*yp*/, sunrealtype* g, void* user_data) {
  auto& d = *static_cast<IdaData*>(user_data);
  try {
    d.form->unpack(t, sun::data(y), d.scratch.state);
    const core::Model& model = d.form->model();
    const int count = model.switching_function_count();
    if (count > 0) {
      model.switching_functions(core::LoadContext{t, d.t_segment}, d.scratch.state,
                                d.scratch.workspace,
                                std::span<double>(g, static_cast<std::size_t>(count)));
    }
    if (model.has_constraints()) {
      model.advance_tracker(t, d.scratch.state, d.tracker, d.scratch.workspace);
      g[count] = d.tracker.rows == d.form->active_rows() ? 1.0 : -1.0;
    }
  } catch (...) {
    d.callback_error = std::current_exception();
    d.failed_callback = "root function";
    return -1;
  }
  return 0;
}

/// F(t, y, y') of the DAE form; allocates nothing.
int residual(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* user_data) {
  auto& d = *static_cast<IdaData*>(user_data);
  try {
    d.form->residual(core::LoadContext{t, d.t_segment}, sun::data(y), sun::data(yp), sun::data(r),
                     d.scratch);
    if (d.completion != nullptr) {
      d.completion->remember(t, d.t_segment, sun::data(y), sun::data(yp), sun::data(r));
    }
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;  // unrecoverable; the driver rethrows the message
  }
  return finite_or_retry(d, t, sun::data(r), d.form->size());
}

/// IDALsJacFn from the user's ODE Jacobian: ∂F/∂y + c_j ∂F/∂y' ≈ P (c_j I − J)
/// (ode_jacobian.hpp); allocates nothing.
int jacobian(sunrealtype t, sunrealtype c_j, N_Vector y, N_Vector /*yp*/, N_Vector /*r*/,
             SUNMatrix matrix, void* user_data, N_Vector /*tmp1*/, N_Vector /*tmp2*/,
             N_Vector /*tmp3*/) {
  auto& d = *static_cast<IdaData*>(user_data);
  const int n = d.form->size();
  try {
    const core::LoadContext context{t, d.t_segment};
    d.ode->rhs(context, sun::data(y), d.f.data(), d.ode_scratch);
    d.jacobian->evaluate(*d.ode, context, sun::data(y), d.f.data(), d.ode_jacobian, d.ode_scratch);
    d.form->mass_rows(context, sun::data(y), d.mass, d.scratch);
    d.ode_jacobian *= -1.0;
    d.ode_jacobian.diagonal().array() += c_j;
    Eigen::Map<Eigen::MatrixXd>(SUNDenseMatrix_Data(matrix), n, n).noalias() =
        d.mass * d.ode_jacobian;
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  return finite_or_retry(d, t, SUNDenseMatrix_Data(matrix), static_cast<long>(n) * n);
}

/// IDALsJacFn of the structured path: J from the StructuredJacobian, then A = I − J/c_j and the
/// factored mass rows (ida_newton_solver.hpp); allocates nothing.
int structured_jacobian(sunrealtype t, sunrealtype c_j, N_Vector y, N_Vector /*yp*/, N_Vector /*r*/,
                        SUNMatrix matrix, void* user_data, N_Vector /*tmp1*/, N_Vector /*tmp2*/,
                        N_Vector /*tmp3*/) {
  auto& d = *static_cast<IdaData*>(user_data);
  const int n = d.form->size();
  try {
    const core::LoadContext context{t, d.t_segment};
    d.structured->evaluate(context, sun::data(y), SUNDenseMatrix_Data(matrix), n,
                           d.structured_scratch);
    if (!d.newton->setup_matrix(context, sun::data(y), c_j, SUNDenseMatrix_Data(matrix),
                                d.scratch)) {
      d.last_nonfinite_time = t;
      return 1;
    }
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  return finite_or_retry(d, t, SUNDenseMatrix_Data(matrix), static_cast<long>(n) * n);
}

/// IDALsJacFn of the sparse path: G = ∂F/∂y + c_j ∂F/∂y' by coloured difference quotients with
/// IDA's increments (dae_coloured_jacobian.hpp) into the CSC matrix KLU factors; the error
/// weights in tmp1, the perturbed residual in tmp2. Allocates nothing but where the rows in force
/// changed (a new pattern, analysed again by KLU).
int coloured_jacobian(sunrealtype t, sunrealtype c_j, N_Vector y, N_Vector yp, N_Vector r,
                      SUNMatrix matrix, void* user_data, N_Vector tmp1, N_Vector tmp2,
                      N_Vector /*tmp3*/) {
  auto& d = *static_cast<IdaData*>(user_data);
  try {
    if (d.coloured->update_pattern()) {
      sun::check(SUNLinSol_KLUReInit(d.klu, matrix, d.coloured->nonzeros(), SUNKLU_REINIT_FULL),
                 "SUNLinSol_KLUReInit");
    }
    double h = 0.0;
    sun::check(IDAGetCurrentStep(d.ida, &h), "IDAGetCurrentStep");
    sun::check(IDAGetErrWeights(d.ida, tmp1), "IDAGetErrWeights");
    const bool finite = d.coloured->evaluate(
        core::LoadContext{t, d.t_segment}, c_j, h, sun::data(y), sun::data(yp), sun::data(r),
        sun::data(tmp1), sun::data(tmp2), d.scratch, SUNSparseMatrix_IndexPointers(matrix),
        SUNSparseMatrix_IndexValues(matrix), SUNSparseMatrix_Data(matrix));
    d.coloured_residuals += d.coloured->group_count();
    if (d.completion != nullptr) d.completion->set_matrix(c_j, sun::data(tmp1));
    if (!finite) {
      d.last_nonfinite_time = t;
      return 1;  // recoverable: IDA retries with a smaller step
    }
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  return 0;
}

}  // namespace flexref::reference::ida
