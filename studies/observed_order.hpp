#pragma once
/// \file observed_order.hpp
/// Observed order of convergence from errors at successively refined steps:
///   pairwise  p_i = log(e_i/e_{i+1}) / log(h_i/h_{i+1})
///   least squares: slope of log e against log h.
#include <vector>

namespace flexref::studies {

/// p_i for i = 0..n−2 (NaN where an error is zero or non-finite).
std::vector<double> pairwise_orders(const std::vector<double>& steps,
                                    const std::vector<double>& errors);

/// Least-squares slope of log e vs log h over the points with use[i] true (NaN when fewer
/// than two usable points).
double least_squares_order(const std::vector<double>& steps, const std::vector<double>& errors,
                           const std::vector<bool>& use);

}  // namespace flexref::studies
