#pragma once
/// \file output_times.hpp
/// The output grid every integrator writes: t_k = k·Δ for k = 0, 1, … while t_k ≤ T, plus T
/// itself when T is not on the grid. Times are computed as k·Δ, never accumulated.
#include <vector>

namespace flexref::core {

/// Throws std::invalid_argument unless end_time > 0 and output_step > 0 (both finite).
std::vector<double> output_times(double end_time, double output_step);

/// True when t is an integer multiple of h to within a relative 1e-9 (step sizes given in
/// decimal are not binary-exact; 1e-9 is far above that representation error, ~1e-16·t/h,
/// and far below any step a scheme is run at).
bool is_multiple_of(double t, double h);

}  // namespace flexref::core
