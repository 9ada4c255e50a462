#pragma once
/// \file cvode_step_clock.hpp
/// CVODE's accepted steps onto the clock that sums them exactly (step_clock.hpp), for the CVODE
/// references of both forms (cvode_solver.cpp, reduced_cvode.cpp).
#include <cvode/cvode.h>

#include "reference/step_clock.hpp"
#include "reference/sundials_handle.hpp"

namespace flexref::reference {

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

}  // namespace flexref::reference
