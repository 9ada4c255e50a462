#include "reference/step_clock.hpp"

namespace flexref::reference {

void StepClock::start_run(double t) {
  run_start_ = t;
  run_steps_ = 0;
  restart(t);
}

void StepClock::restart(double t) {
  seen_steps_ = 0;
  solver_time_ = t;
  sum_ = t;
  compensation_ = 0.0;
}

void StepClock::record(long steps, double last_step, double solver_time) {
  if (steps == seen_steps_ + 1) {
    // Knuth's TwoSum: s = fl(a + b) and the exact rounding error e, a + b = s + e.
    const double a = sum_, b = last_step;
    const double s = a + b;
    const double b_virtual = s - a;
    const double e = (a - (s - b_virtual)) + (b - b_virtual);
    sum_ = s;
    compensation_ += e;
    solver_time_ = solver_time;
    ++run_steps_;
  } else if (steps > seen_steps_ + 1) {
    run_steps_ += steps - seen_steps_;
    sum_ = solver_time;
    compensation_ = 0.0;
    solver_time_ = solver_time;
  }
  if (steps > seen_steps_) seen_steps_ = steps;
}

double StepClock::mean_step() const {
  if (run_steps_ == 0) return 0.0;
  return ((sum_ - run_start_) + compensation_) / static_cast<double>(run_steps_);
}

}  // namespace flexref::reference
