#pragma once
/// \file run_scheme.hpp
/// Fixed-step driver of a Stepper over an output grid.
#include <atomic>
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"
#include "lie/stepper.hpp"

namespace flexref::lie {

/// Checks a fixed step against an output grid before any work and returns the number of steps
/// from output_times.front() to output_times.back(). Throws std::invalid_argument, naming the
/// offending time and the step, when dt is not positive and finite, the output times are empty,
/// not finite or not strictly increasing, dt is longer than the run or than an output interval
/// (said in those words), an output time or a load discontinuity in (t0, t_end] is not t0 plus
/// an integer multiple of dt (core::is_multiple_of), or dt is below
/// what double precision resolves at the grid's times (core::smallest_resolved_step of
/// max(|t0|, |t_end|): the stepper's h_n = t_{n+1} − t_n must equal dt to 1e-6 relative; this
/// also keeps the step count far below the range of `long`).
long validate_step_grid(const core::Model& model, double dt,
                        const std::vector<double>& output_times);

/// Integrates from model.initial_state() at t0 = output_times.front() with the fixed step dt,
/// t_n = t0 + n·dt (computed by multiplication, never accumulated; the stepper is given
/// h_n = t_{n+1} − time(), which makes its own clock land on t_{n+1}), and returns the states
/// at the output times (the times themselves as given).
///
/// Throws std::invalid_argument as validate_step_grid does. Throws core::SolverError(stepper
/// name, t_n, n, why) when step n (from t_n) fails or leaves a non-finite state, or when the
/// energy (kinetic + potential) at an output time is not finite: no trajectory with an inf or
/// a NaN is ever returned.
///
/// `steps_done`, when given, is set to the number of steps taken after each step (relaxed
/// atomic store), for a progress line drawn by another thread.
core::Trajectory run_scheme(const core::Model& model, Stepper& stepper, double dt,
                            const std::vector<double>& output_times,
                            std::atomic<long>* steps_done = nullptr);

}  // namespace flexref::lie
