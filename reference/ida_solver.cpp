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
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "reference/dae_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/sundials_handle.hpp"

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

/// Adds the counters of the current IDA run (they restart at every IDAReInit).
void add_counters(void* ida, SolverStats& stats) {
  long steps = 0, residuals = 0, jacobian_residuals = 0, jacobians = 0, error_fails = 0,
       convergence_fails = 0;
  sun::check(IDAGetNumSteps(ida, &steps), "IDAGetNumSteps");
  sun::check(IDAGetNumResEvals(ida, &residuals), "IDAGetNumResEvals");
  sun::check(IDAGetNumLinResEvals(ida, &jacobian_residuals), "IDAGetNumLinResEvals");
  sun::check(IDAGetNumJacEvals(ida, &jacobians), "IDAGetNumJacEvals");
  sun::check(IDAGetNumErrTestFails(ida, &error_fails), "IDAGetNumErrTestFails");
  sun::check(IDAGetNumNonlinSolvConvFails(ida, &convergence_fails), "IDAGetNumNonlinSolvConvFails");
  stats.steps += steps;
  stats.rhs_evaluations += residuals + jacobian_residuals;
  stats.jacobian_evaluations += jacobians;
  stats.error_test_failures += error_fails;
  stats.nonlinear_failures += convergence_fails;
}

}  // namespace

ReferenceRun solve_ida(const core::Model& model, const std::vector<double>& output_times,
                       const SolverOptions& options) {
  sun::validate_tolerances(options.rtol, options.absolute_tolerance(), options.max_steps);
  const sun::SegmentPlan plan = sun::plan_segments(model.discontinuities(), output_times);
  const reference::DaeForm form(model);
  const int n = form.size();

  ReferenceRun run;
  run.solver = "ida";
  run.options = options;
  run.trajectory.times = output_times;
  run.trajectory.states.reserve(output_times.size());
  core::State state = model.initial_state();
  const bool track_work = form.work_index() >= 0;
  double work = 0.0;  // W_d carried across restarts
  for (std::size_t k = 0; k < plan.initial_outputs; ++k) {
    run.trajectory.states.push_back(state);
    if (track_work) run.trajectory.dissipated_work.push_back(0.0);
  }
  if (plan.segments.empty()) return run;

  IdaData data;
  data.form = &form;
  data.scratch = form.make_scratch();

  const sun::Context context = sun::make_context();
  const sun::Vector y = sun::make_vector(n, context.get());
  const sun::Vector yp = sun::make_vector(n, context.get());
  const sun::Vector ids = sun::make_vector(n, context.get());
  const sun::Vector atol = sun::make_vector(n, context.get());
  const std::vector<double> differential = form.differential_ids();
  for (int i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    sun::data(ids.get())[i] = differential[u];
    sun::data(atol.get())[i] =
        differential[u] > 0.0 ? options.absolute_tolerance() : kMultiplierAbsoluteTolerance;
  }
  const sun::Matrix jacobian = sun::make_dense_matrix(n, context.get());
  const sun::LinearSolver linear_solver =
      sun::make_dense_linear_solver(y.get(), jacobian.get(), context.get());
  // Declared last so that it is freed first (as in SUNDIALS' examples).
  const sun::IdaMemory ida(sun::check_created(IDACreate(context.get()), "IDACreate"));

  double t_reached = 0.0;
  std::clock_t cpu = 0;
  try {
    bool initialized = false;
    for (const sun::Segment& segment : plan.segments) {
      const std::clock_t start = std::clock();
      data.t_segment = segment.t_segment;
      // Consistent (y, y') on the new load branch: λ = μ = 0, y' from the ODE form.
      form.initial_values(core::LoadContext{segment.start, segment.t_segment}, state,
                          sun::data(y.get()), sun::data(yp.get()));
      form.set_dissipated_work(sun::data(y.get()), work);
      if (!sun::all_finite(sun::data(y.get()), n) || !sun::all_finite(sun::data(yp.get()), n)) {
        throw core::SolverError("ida", segment.start, run.stats.steps,
                                "the loads are not finite at the initial state of the segment");
      }
      if (!initialized) {
        sun::check(IDAInit(ida.get(), residual, segment.start, y.get(), yp.get()), "IDAInit");
        sun::check(IDASetUserData(ida.get(), &data), "IDASetUserData");
        sun::check(IDASetErrHandlerFn(ida.get(), sun::record_error, &data.log),
                   "IDASetErrHandlerFn");
        sun::check(IDASVtolerances(ida.get(), options.rtol, atol.get()), "IDASVtolerances");
        sun::check(IDASetLinearSolver(ida.get(), linear_solver.get(), jacobian.get()),
                   "IDASetLinearSolver");
        sun::check(IDASetId(ida.get(), ids.get()), "IDASetId");
        sun::check(IDASetSuppressAlg(ida.get(), SUNTRUE), "IDASetSuppressAlg");
        sun::check(IDASetMaxNumSteps(ida.get(), options.max_steps), "IDASetMaxNumSteps");
        sun::check(IDASetDeltaCjLSetup(ida.get(), 0.0), "IDASetDeltaCjLSetup");
        if (model.switching_function_count() > 0) {
          sun::check(IDARootInit(ida.get(), model.switching_function_count(), switching),
                     "IDARootInit");
        }
        initialized = true;
      } else {
        sun::check(IDAReInit(ida.get(), segment.start, y.get(), yp.get()), "IDAReInit");
      }
      sun::check(IDASetStopTime(ida.get(), segment.end), "IDASetStopTime");
      t_reached = segment.start;
      cpu += std::clock() - start;

      const auto advance_to = [&](double tout) {
        const std::clock_t solve_start = std::clock();
        double t_returned = t_reached;
        while (t_returned < tout) {
          const int flag = IDASolve(ida.get(), tout, &t_returned, y.get(), yp.get(), IDA_NORMAL);
          sun::check(flag, "IDASolve");
          if (flag == IDA_ROOT_RETURN) {
            // A contact onset or release: restart there from consistent values.
            run.event_times.push_back(t_returned);
            ++run.stats.events;
            add_counters(ida.get(), run.stats);
            form.unpack(t_returned, sun::data(y.get()), state);
            const double work_at_event = form.dissipated_work(sun::data(y.get()));
            form.initial_values(core::LoadContext{t_returned, segment.t_segment}, state,
                                sun::data(y.get()), sun::data(yp.get()));
            form.set_dissipated_work(sun::data(y.get()), work_at_event);
            sun::check(IDAReInit(ida.get(), t_returned, y.get(), yp.get()), "IDAReInit");
            sun::check(IDASetStopTime(ida.get(), segment.end), "IDASetStopTime");
          } else {
            t_returned = tout;
          }
        }
        cpu += std::clock() - solve_start;
        t_reached = tout;
      };
      for (std::size_t k = segment.first_output; k < segment.end_output; ++k) {
        // Outputs within boundary_slack of the segment end are taken at the end.
        const double tout = std::min(output_times[k], segment.end);
        if (tout > t_reached) advance_to(tout);
        form.unpack(tout, sun::data(y.get()), state);
        run.trajectory.states.push_back(state);
        if (track_work)
          run.trajectory.dissipated_work.push_back(form.dissipated_work(sun::data(y.get())));
      }
      if (t_reached < segment.end) advance_to(segment.end);
      // The state is continuous across a load switch; unpacking normalizes θ, so the restart
      // also projects the Euler parameters back onto the unit sphere.
      form.unpack(t_reached, sun::data(y.get()), state);
      work = form.dissipated_work(sun::data(y.get()));
      add_counters(ida.get(), run.stats);
    }
  } catch (const sun::SundialsError& e) {
    double t_failed = t_reached;
    long steps = 0;
    if (IDAGetCurrentTime(ida.get(), &t_failed) < 0) t_failed = t_reached;
    if (IDAGetNumSteps(ida.get(), &steps) < 0) steps = 0;
    throw core::SolverError("ida", t_failed, run.stats.steps + steps,
                            sun::failure_message(e.what(), data, "residual"));
  }
  run.stats.cpu_seconds = static_cast<double>(cpu) / CLOCKS_PER_SEC;
  return run;
}

}  // namespace flexref::reference
