#pragma once
/// \file step_clock.hpp
/// The exact elapsed time of a multistep solver's accepted steps (docs/references.md, "The
/// solvers' clock"). CVODE and IDA advance their time by t_n ← fl(t_{n−1} + h_n); with h held
/// for long runs of steps (CVODE changes h only when it can grow 1.5×, IDA only when it can
/// double) the rounding errors of that sum have a bias, and the state the solver carries is the
/// solution at Σ h_n, not at t_n. A body spinning at ω then shows a phase error ω (t_n − Σ h_n):
/// measured on heavy_top (150 rad/s) with 400 000 steps of h = 5e-6 s, t_n − Σ h_n = 8.9e-12 s
/// and the attitude error 1.33e-9 rad, whatever the solver (IDA, ARKODE forced to that step)
/// and the tolerance. The clock sums the steps with Knuth's TwoSum (the sum and its rounding
/// error, exact to ~1e-32 s), so the driver can report the state at the physical time it was
/// asked for: y(t) = y_solver(t + δ) ≈ y_solver(t) + δ ẏ_solver(t), δ = t_n − Σ h_n
/// (offset()); δ ≲ 1e-11 s, so the neglected ½ δ² ÿ is below 1e-18 of any state.
///
/// The solvers report their steps through their error-weight callback, which CVODE and IDA call
/// once before every step after the first (and through the driver after each return): record()
/// takes the solver's step count, its last step and its current time, and adds the step when
/// the count has advanced by one. The clock also gives the run's mean step (error_weights.hpp).

namespace flexref::reference {

class StepClock {
 public:
  /// The run starts at t (its first segment's start): no steps, the clocks agree.
  void start_run(double t);
  /// The solver was (re)initialized at t: its step count restarts from 0 and its time is t,
  /// which is also the physical time of the state it starts from.
  void restart(double t);
  /// The solver's step count `steps` (since its last initialization), its last accepted step
  /// `last_step` and its current time `solver_time`. Adds `last_step` when `steps` is one more
  /// than at the previous call; when more steps passed unseen, the clock cannot know their sum
  /// and takes the solver's time as exact from then on (offset 0 until the next restart).
  void record(long steps, double last_step, double solver_time);

  /// δ = t_solver − Σ h (s) at the solver's time of the last record(): the solver's state is the
  /// solution at its time minus δ.
  double offset() const { return (solver_time_ - sum_) - compensation_; }
  /// The mean accepted step of the run so far (s), or 0 before its first step.
  double mean_step() const;
  /// Accepted steps of the run so far (over every restart).
  long run_steps() const { return run_steps_; }

 private:
  double run_start_ = 0.0;
  long run_steps_ = 0;
  long seen_steps_ = 0;  ///< the solver's count at the last record()
  double solver_time_ = 0.0;
  double sum_ = 0.0;           ///< Σ h, rounded …
  double compensation_ = 0.0;  ///< … and what the rounding lost (Σ h = sum_ + compensation_)
};

}  // namespace flexref::reference
