/// \file ida_solver.cpp
/// IDA (variable-order BDF for DAEs) on the Euler-parameter DAE form of docs/design/model.md
/// (reference/dae_form.hpp: Gear–Gupta–Leimkuhler stabilized index 2, multipliers λ, μ).
///
/// - Dense direct linear solver with IDA's difference-quotient Jacobian (the systems are
///   10–16 unknowns per body; an analytic Jacobian would save little and is one more thing to
///   get wrong).
/// - λ and μ are marked algebraic (IDASetId) and left out of the local error test
///   (IDASetSuppressAlg): the index-2 multipliers cannot be controlled like the states, and on
///   a solution they are zero anyway (they only measure the discretization's drift).
/// - [0, T] is integrated segment by segment between the model's known load discontinuities:
///   IDASetStopTime at each segment end, then IDAReInit from the state there with consistent
///   (y, y') from DaeForm::initial_values on the new load branch. Every residual call passes
///   t_segment = the segment's midpoint.
/// - Outputs: IDASolve in IDA_NORMAL mode with tout = each requested time, which IDA fills from
///   its own interpolating polynomial (the solver's dense output), never beyond the stop time.
/// - One setting away from IDA's defaults, measured on free_spin, book_toss and coulomb_wall:
///   the iteration matrix is rebuilt whenever cj = α/h changes (IDASetDeltaCjLSetup(0)).
///   In Euler-parameter coordinates the dominant block cj·4ḠᵀIḠ turns with the body, so the
///   default reuse (until cj changes by 25 % or Newton fails) iterates with a stale matrix:
///   free_spin at rtol 1e-10 took ~560 convergence failures per 100 s, and the accepted,
///   half-converged iterates biased the energy (drift 3.7e-6 against 3e-8 for CVODE). With the
///   rebuild there are no convergence failures, and the error at rtol 1e-12 drops ~50× (5e-9
///   instead of 2.6e-7 rad over 100 s) at the same CPU time (15 % fewer steps pay for the
///   ~4× more Jacobians).
/// - Switching functions (contact gaps, core::Model::switching_functions): IDARootInit
///   locates their zeros; at each (IDA_ROOT_RETURN) the time is recorded and IDA restarts
///   there from consistent values, so no step straddles a contact onset or release.
/// - SolverOptions::max_steps is IDA's mxstep: the most steps taken to reach one output time.
///
/// Accuracy per rtol is lower than CVODE's on the same model. In the DAE form a steady spin
/// is carried by v_θ, which oscillates at |ω̄|/2, and BDF damps oscillations by a one-signed
/// amplitude error each step: |ω̄| = 2|v_θ| and the energy drift systematically (in the ODE
/// form ω̄ is constant in a steady spin and only θ oscillates, and θ is projected). Measured:
/// free_spin energy drift ~20× CVODE's at rtol 1e-10; on book_toss the pulse leaves an energy
/// error of 4e-11 relative at rtol 1e-12 (CVODE < 1e-14), which the near-separatrix motion
/// amplifies to a maximum attitude error of 7e-5 rad over 10 s (CVODE 4e-8); even at
/// rtol 1e-14 IDA stays at ~5e-6 there. Use IDA as the independent DAE cross-check, with
/// bounds derived for it, not as the tightest reference on sensitive scenes.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <ctime>
#include <exception>
#include <limits>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "reference/dae_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_segment_driver.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;

/// Absolute tolerance of λ and μ. They are out of the error test, but IDA's Newton iteration
/// still weighs their corrections with 1/(rtol |y| + atol) in its convergence test. Since
/// λ = μ = 0 on the solution, the states' tolerance would ask for multipliers converged far
/// below the size of their residual rows' round-off: with atol = 1e-12 for them IDA crawled
/// (free_spin at rtol 1e-10 did not finish in minutes). Any value from 1e-6 to 1e3 gave the
/// same solutions (errors within 10 %); 1, in the units of λ and μ, is the round middle.
constexpr double kMultiplierAbsoluteTolerance = 1.0;

struct IdaData : sun::CallbackRecord {
  const reference::DaeForm* form = nullptr;
  reference::DaeForm::Scratch scratch;
  double t_segment = 0.0;
};

/// The model's switching functions at (t, y); allocates nothing.
int switching(sunrealtype t, N_Vector y, N_Vector /*yp*/, sunrealtype* g, void* user_data) {
  auto& d = *static_cast<IdaData*>(user_data);
  try {
    d.form->unpack(t, sun::data(y), d.scratch.state);
    const core::Model& model = d.form->model();
    model.switching_functions(
        core::LoadContext{t, d.t_segment}, d.scratch.state, d.scratch.workspace,
        std::span<double>(g, static_cast<std::size_t>(model.switching_function_count())));
  } catch (...) {
    d.callback_error = std::current_exception();
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
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;  // unrecoverable; the driver rethrows the message
  }
  if (!sun::all_finite(sun::data(r), d.form->size())) {
    // Recoverable: a trial step may have reached a singular load (a charge on the wall); IDA
    // retries with a smaller step and gives up with its own message if that does not help.
    d.last_nonfinite_time = t;
    return 1;
  }
  return 0;
}

/// IDA on the DAE form, driven segment by segment by integrate_segments.
class IdaSegmentSolver final : public sun::SegmentSolver {
 public:
  IdaSegmentSolver(const core::Model& model, const SolverOptions& options)
      : model_(&model),
        options_(options),
        form_(model),
        context_(sun::make_context()),
        y_(sun::make_vector(form_.size(), context_.get())),
        yp_(sun::make_vector(form_.size(), context_.get())),
        ids_(sun::make_vector(form_.size(), context_.get())),
        atol_(sun::make_vector(form_.size(), context_.get())),
        jacobian_(sun::make_dense_matrix(form_.size(), context_.get())),
        linear_solver_(sun::make_dense_linear_solver(y_.get(), jacobian_.get(), context_.get())),
        ida_(sun::check_created(IDACreate(context_.get()), "IDACreate")) {
    data_.form = &form_;
    data_.scratch = form_.make_scratch();
    const std::vector<double> differential = form_.differential_ids();
    for (int i = 0; i < form_.size(); ++i) {
      const auto u = static_cast<std::size_t>(i);
      sun::data(ids_.get())[i] = differential[u];
      sun::data(atol_.get())[i] =
          differential[u] > 0.0 ? options.absolute_tolerance() : kMultiplierAbsoluteTolerance;
    }
  }

  void start_segment(const sun::Segment& segment, const core::State& state, double work) override {
    data_.t_segment = segment.t_segment;
    // Consistent (y, y') on the new load branch: λ = μ = 0, y' from the ODE form.
    form_.initial_values(core::LoadContext{segment.start, segment.t_segment}, state,
                         sun::data(y_.get()), sun::data(yp_.get()));
    form_.set_dissipated_work(sun::data(y_.get()), work);
    const int n = form_.size();
    if (!sun::all_finite(sun::data(y_.get()), n) || !sun::all_finite(sun::data(yp_.get()), n)) {
      throw sun::StartError("the loads are not finite at the initial state of the segment");
    }
    if (!initialized_) {
      void* ida = ida_.get();
      sun::check(IDAInit(ida, residual, segment.start, y_.get(), yp_.get()), "IDAInit");
      sun::check(IDASetUserData(ida, &data_), "IDASetUserData");
      sun::check(IDASetErrHandlerFn(ida, sun::record_error, &data_.log), "IDASetErrHandlerFn");
      sun::check(IDASVtolerances(ida, options_.rtol, atol_.get()), "IDASVtolerances");
      sun::check(IDASetLinearSolver(ida, linear_solver_.get(), jacobian_.get()),
                 "IDASetLinearSolver");
      sun::check(IDASetId(ida, ids_.get()), "IDASetId");
      sun::check(IDASetSuppressAlg(ida, SUNTRUE), "IDASetSuppressAlg");
      sun::check(IDASetMaxNumSteps(ida, options_.max_steps), "IDASetMaxNumSteps");
      sun::check(IDASetDeltaCjLSetup(ida, 0.0), "IDASetDeltaCjLSetup");
      if (model_->switching_function_count() > 0) {
        sun::check(IDARootInit(ida, model_->switching_function_count(), switching), "IDARootInit");
      }
      initialized_ = true;
    } else {
      sun::check(IDAReInit(ida_.get(), segment.start, y_.get(), yp_.get()), "IDAReInit");
    }
    sun::check(IDASetStopTime(ida_.get(), segment.end), "IDASetStopTime");
  }

  Advance advance(double tout) override {
    Advance reached;
    const int flag = IDASolve(ida_.get(), tout, &reached.t, y_.get(), yp_.get(), IDA_NORMAL);
    sun::check(flag, "IDASolve");
    reached.root = flag == IDA_ROOT_RETURN;
    return reached;
  }

  void restart_at_root(double t, const sun::Segment& segment) override {
    // Restart from consistent values at the event.
    form_.unpack(t, sun::data(y_.get()), data_.scratch.state);
    const double work_at_event = form_.dissipated_work(sun::data(y_.get()));
    form_.initial_values(core::LoadContext{t, segment.t_segment}, data_.scratch.state,
                         sun::data(y_.get()), sun::data(yp_.get()));
    form_.set_dissipated_work(sun::data(y_.get()), work_at_event);
    sun::check(IDAReInit(ida_.get(), t, y_.get(), yp_.get()), "IDAReInit");
    sun::check(IDASetStopTime(ida_.get(), segment.end), "IDASetStopTime");
  }

  void unpack(double t, core::State& state) const override {
    form_.unpack(t, sun::data(y_.get()), state);
  }
  double dissipated_work() const override { return form_.dissipated_work(sun::data(y_.get())); }

  void add_counters(SolverStats& stats) const override {
    void* ida = ida_.get();
    long steps = 0, residuals = 0, jacobian_residuals = 0, jacobians = 0, error_fails = 0,
         convergence_fails = 0;
    sun::check(IDAGetNumSteps(ida, &steps), "IDAGetNumSteps");
    sun::check(IDAGetNumResEvals(ida, &residuals), "IDAGetNumResEvals");
    sun::check(IDAGetNumLinResEvals(ida, &jacobian_residuals), "IDAGetNumLinResEvals");
    sun::check(IDAGetNumJacEvals(ida, &jacobians), "IDAGetNumJacEvals");
    sun::check(IDAGetNumErrTestFails(ida, &error_fails), "IDAGetNumErrTestFails");
    sun::check(IDAGetNumNonlinSolvConvFails(ida, &convergence_fails),
               "IDAGetNumNonlinSolvConvFails");
    stats.steps += steps;
    stats.rhs_evaluations += residuals + jacobian_residuals;
    stats.jacobian_evaluations += jacobians;
    stats.error_test_failures += error_fails;
    stats.nonlinear_failures += convergence_fails;
  }

  double current_time(double fallback) const override {
    double t = fallback;
    return IDAGetCurrentTime(ida_.get(), &t) < 0 ? fallback : t;
  }
  long current_steps() const override {
    long steps = 0;
    return IDAGetNumSteps(ida_.get(), &steps) < 0 ? 0 : steps;
  }
  std::string failure_message(const std::string& what) const override {
    return sun::failure_message(what, data_, "residual");
  }

 private:
  const core::Model* model_;
  SolverOptions options_;
  reference::DaeForm form_;
  IdaData data_;
  bool initialized_ = false;
  sun::Context context_;
  sun::Vector y_, yp_, ids_, atol_;
  sun::Matrix jacobian_;
  sun::LinearSolver linear_solver_;
  // Declared last so that it is freed first (as in SUNDIALS' examples).
  sun::IdaMemory ida_;
};

}  // namespace

ReferenceRun solve_ida(const core::Model& model, const std::vector<double>& output_times,
                       const SolverOptions& options) {
  return sun::integrate_segments(model, output_times, options, "ida", [&] {
    return std::make_unique<IdaSegmentSolver>(model, options);
  });
}

}  // namespace flexref::reference
