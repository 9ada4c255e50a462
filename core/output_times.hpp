#pragma once
/// \file output_times.hpp
/// The output grid every integrator writes: t_k = k·Δ for k = 0, 1, … while t_k ≤ T, plus T
/// itself when T is not on the grid. Times are computed as k·Δ, never accumulated.
#include <vector>

namespace flexref::core {

/// Throws std::invalid_argument unless end_time > 0 and output_step > 0 (both finite).
std::vector<double> output_times(double end_time, double output_step);

/// The smallest step that double precision resolves at times up to |t|: times near t are
/// rounded to ε·|t|, and a step taken as t_{n+1} − t_n equals the intended step to 1e-6
/// relative only when it spans at least 1e6 such roundings: 1e6·ε·|t| (2.2e-9 s at t = 10 s).
/// Fixed steps below it are refused (lie::validate_step_grid), and so are scenes whose fastest
/// motion has a period below it (nothing can integrate them).
double smallest_resolved_step(double t);

/// True when t is an integer multiple of h to within a relative 1e-9 (step sizes given in
/// decimal are not binary-exact; 1e-9 is far above that representation error, ~1e-16·t/h,
/// and far below any step a scheme is run at).
bool is_multiple_of(double t, double h);

}  // namespace flexref::core
