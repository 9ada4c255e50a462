#pragma once
/// \file observed_order.hpp
/// Observed order of convergence from errors at successively refined steps:
///   pairwise  p_i = log(e_i/e_{i+1}) / log(h_i/h_{i+1})
///   least squares: slope of log e against log h;
/// and, without the exact solution, from the distances between solutions at successive steps.
#include <vector>

namespace flexref::studies {

/// p_i for i = 0..n−2 (NaN where an error is zero or non-finite).
std::vector<double> pairwise_orders(const std::vector<double>& steps,
                                    const std::vector<double>& errors);

/// Least-squares slope of log e vs log h over the points with use[i] true (NaN when fewer
/// than two usable points).
double least_squares_order(const std::vector<double>& steps, const std::vector<double>& errors,
                           const std::vector<bool>& use);

/// The distance ‖u(h_coarse) − u(h_fine)‖ between the solutions of two levels, h_coarse > h_fine.
struct LevelDistance {
  double coarse = 0.0;
  double fine = 0.0;
  double distance = 0.0;
};

/// The observed order from distances between solutions (the observed order of accuracy without
/// an exact solution: Roache 1998, cited in docs/wear.md), for a method that converges to a limit
/// u* that need not be the reference's solution: u(h) = u* + C h^p gives d = C (h_c^p − h_f^p), and
/// p minimizes the least-squares residual of log d = log C + log(h_c^p − h_f^p) over the pairs, C
/// eliminated (for pairs of one ratio h_c/h_f, the slope of log d against log h_c). A limit u* ≠
/// the reference (a floor every level shares) cancels from the distances. NaN from fewer than two
/// pairs with a finite positive distance, or when no p in [0.05, 10] fits (the residual's
/// minimum on that interval's boundary).
double distance_order(const std::vector<LevelDistance>& pairs);

}  // namespace flexref::studies
