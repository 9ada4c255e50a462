#pragma once
/// \file roundoff_scale.hpp
/// The size that multiplies u × evaluations in the round-off part of an extended or quad
/// reference's error estimate (docs/precision.md, "Error estimate").
#include <string>

#include "studies/trajectory_table.hpp"

namespace flexref::precision {

/// studies::solution_scale(table, metric) (π for the rotation, the tracked points' largest
/// distance from the origin at t0) plus what the trajectory sweeps: for the rotation, the
/// largest angle a body turns through, ∫|ω̄| dt (trapezoid over the outputs of B.W1..B.W3); for
/// the points, the longest path of a tracked point (the polyline through its outputs).
///
/// Why the sweep: an evaluation rounds the rates it computes by u relative; an error u|ω| in
/// a body's rate persists and turns its attitude by up to u|ω|(T − t) ≤ u ∫|ω̄| dt, and an
/// error u|v| in a velocity moves a point by up to u × its path. Summed over the evaluations
/// without cancellation, u × evaluations × this scale bounds the round-off. The t0 extent alone
/// did not: a free body spinning at 200 rad/s for 10 s in extended lay 2.0e-13 rad from quad,
/// above u × 417 672 evaluations × (π + 1) = 9.3e-14 (tests/precision/roundoff_scale_test.cpp).
double roundoff_scale(const studies::TrajectoryTable& table, const std::string& metric);

}  // namespace flexref::precision
