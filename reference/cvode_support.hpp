#pragma once
/// \file cvode_support.hpp
/// What the CVODE references of both forms (cvode_solver.cpp on the maximal form,
/// reduced_cvode.cpp on joint coordinates) do alike with a CVODE handle: the accepted steps onto
/// the exact clock (step_clock.hpp), fixed-point iteration in windows with the switch to Newton
/// where it stalls, and the counters.
#include <cvode/cvode.h>

#include <functional>

#include "reference/reference_solver.hpp"
#include "reference/step_clock.hpp"
#include "reference/sundials_handle.hpp"

namespace flexref::reference {

/// Steps fixed-point iteration takes between two looks at its convergence failures
/// (advance_fixed_point).
inline constexpr long kStiffnessWindow = 200;

/// Adds CVODE's accepted steps since the last call to the clock.
inline void record_cvode_steps(void* cvode, StepClock& clock) {
  long steps = 0;
  double last_step = 0.0, t = 0.0;
  sundials::check(CVodeGetNumSteps(cvode, &steps), "CVodeGetNumSteps");
  if (steps == 0) return;
  sundials::check(CVodeGetLastStep(cvode, &last_step), "CVodeGetLastStep");
  sundials::check(CVodeGetCurrentTime(cvode, &t), "CVodeGetCurrentTime");
  clock.record(steps, last_step, t);
}

/// Moves y, CVODE's solution at its time t, to the physical time t (step_clock.hpp):
/// y(t + δ) ≈ y(t) + δ ẏ(t), δ the clock's offset after the steps CVODE took so far; `ydot`
/// scratch of y's size.
inline void to_physical_time(void* cvode, StepClock& clock, double t, N_Vector y, N_Vector ydot) {
  record_cvode_steps(cvode, clock);
  const double offset = clock.offset();
  if (offset == 0.0) return;
  sundials::check(CVodeGetDky(cvode, t, 1, ydot), "CVodeGetDky");
  N_VLinearSum(1.0, y, offset, ydot, y);
}

/// CVODE's current time, or `fallback` where it has none (a failure report).
inline double cvode_current_time(void* cvode, double fallback) {
  double t = fallback;
  return CVodeGetCurrentTime(cvode, &t) < 0 ? fallback : t;
}

/// CVODE's steps since its last (re)initialization, 0 where it cannot say.
inline long cvode_steps(void* cvode) {
  long steps = 0;
  return CVodeGetNumSteps(cvode, &steps) < 0 ? 0 : steps;
}

/// CVode towards tout in CV_NORMAL mode with fixed-point iteration, which the handle runs with
/// CVodeSetMaxNumSteps(kStiffnessWindow): where its corrector fails to converge in a tenth of a
/// window's steps the problem has become stiff (a mechanism approaching a dead point: the
/// multipliers' Lipschitz constant grows without bound, and fixed-point steps would shrink
/// towards it for ever), and `switch_to_newton(t)` makes the rest of the run iterate by Newton —
/// LSODA's switch, one way. `max_steps` (the user's) still bounds the steps to tout. Returns
/// CVode's flag; `reached` is where it stopped.
inline int advance_fixed_point(void* cvode, double tout, N_Vector y, double& reached,
                               long max_steps,
                               const std::function<void(double)>& switch_to_newton) {
  long taken = 0;
  for (;;) {
    long steps0 = 0, fails0 = 0, steps1 = 0, fails1 = 0;
    CVodeGetNumSteps(cvode, &steps0);
    CVodeGetNumNonlinSolvConvFails(cvode, &fails0);
    const int flag = CVode(cvode, tout, y, &reached, CV_NORMAL);
    if (flag != CV_TOO_MUCH_WORK) return flag;
    CVodeGetNumSteps(cvode, &steps1);
    CVodeGetNumNonlinSolvConvFails(cvode, &fails1);
    taken += steps1 - steps0;
    if (taken >= max_steps) return flag;
    if (10 * (fails1 - fails0) >= steps1 - steps0) {
      switch_to_newton(reached);
      return CVode(cvode, tout, y, &reached, CV_NORMAL);
    }
  }
}

/// The end of a switch from fixed-point to Newton iteration at t (advance_fixed_point), the
/// Newton and linear solvers attached: the user's step budget back, CVODE re-initialized from y
/// (its counters restart: the caller keeps them first), the clock restarted there, the
/// segment's stop time set again.
inline void restart_with_newton(void* cvode, double t, N_Vector y, long max_steps,
                                double segment_end, StepClock& clock) {
  sundials::check(CVodeSetMaxNumSteps(cvode, max_steps), "CVodeSetMaxNumSteps");
  sundials::check(CVodeReInit(cvode, t, y), "CVodeReInit");
  clock.restart(t);
  sundials::check(CVodeSetStopTime(cvode, segment_end), "CVodeSetStopTime");
}

/// Adds the counters of CVODE's current run to `stats`, with `before_switch` (the run's counters
/// up to a switch to Newton, which re-initialized CVODE); `newton`: the linear solver's counters
/// exist.
inline void add_cvode_counters(void* cvode, bool newton, const SolverStats& before_switch,
                               SolverStats& stats) {
  long steps = 0, rhs_evaluations = 0, jacobian_rhs = 0, jacobians = 0, error_fails = 0,
       convergence_fails = 0;
  sundials::check(CVodeGetNumSteps(cvode, &steps), "CVodeGetNumSteps");
  sundials::check(CVodeGetNumRhsEvals(cvode, &rhs_evaluations), "CVodeGetNumRhsEvals");
  if (newton) {
    sundials::check(CVodeGetNumLinRhsEvals(cvode, &jacobian_rhs), "CVodeGetNumLinRhsEvals");
    sundials::check(CVodeGetNumJacEvals(cvode, &jacobians), "CVodeGetNumJacEvals");
  }
  sundials::check(CVodeGetNumErrTestFails(cvode, &error_fails), "CVodeGetNumErrTestFails");
  sundials::check(CVodeGetNumNonlinSolvConvFails(cvode, &convergence_fails),
                  "CVodeGetNumNonlinSolvConvFails");
  stats.steps += steps + before_switch.steps;
  stats.rhs_evaluations += rhs_evaluations + jacobian_rhs + before_switch.rhs_evaluations;
  stats.jacobian_evaluations += jacobians;
  stats.error_test_failures += error_fails + before_switch.error_test_failures;
  stats.nonlinear_failures += convergence_fails + before_switch.nonlinear_failures;
}

}  // namespace flexref::reference
