#pragma once
/// \file run_scheme.hpp
/// Fixed-step driver of a Stepper over an output grid.
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"
#include "lie/stepper.hpp"

namespace flexref::lie {

/// Integrates from model.initial_state() at t0 = output_times.front() with the fixed step dt,
/// t_n = t0 + n·dt (computed by multiplication, never accumulated; the stepper is given
/// h_n = t_{n+1} − time(), which makes its own clock land on t_{n+1}), and returns the states
/// at the output times (the times themselves as given).
///
/// Throws std::invalid_argument when dt is not positive and finite, the output times are
/// empty, not finite or not strictly increasing, or an output time or a load discontinuity in
/// (t0, t_end] is not t0 plus an integer multiple of dt (core::is_multiple_of): the message
/// names the offending time and the step. Throws core::SolverError(stepper name, t_n, n, why)
/// when step n (from t_n) fails or leaves a non-finite state.
core::Trajectory run_scheme(const core::Model& model, Stepper& stepper, double dt,
                            const std::vector<double>& output_times);

}  // namespace flexref::lie
