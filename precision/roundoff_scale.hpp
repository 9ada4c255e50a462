#pragma once
/// \file roundoff_scale.hpp
/// The size that multiplies u × evaluations in the round-off part of an extended or quad
/// reference's error estimate (docs/precision.md, "Error estimate").
#include <span>
#include <string>
#include <vector>

#include "trajectory/trajectory_table.hpp"

namespace flexref::scene {
struct SceneSpec;
}

namespace flexref::precision {

/// A tracked point at node k of a flexible body: its columns' stem "<B>.<P>" and ‖Φ_k‖_F, which
/// bounds its elastic speed, |A Φ_k q̇_f| ≤ ‖Φ_k‖_F |q̇_f| (‖·‖₂ ≤ ‖·‖_F; q̇_f from the body's
/// qd columns).
struct NodePoint {
  std::string stem;
  double shape_norm = 0.0;
};
/// The scene's tracked points at nodes (hub points and rigid bodies' points have none).
std::vector<NodePoint> node_points(const scene::SceneSpec& spec);

/// trajectory::solution_scale(table, metric) (π for the rotation, the tracked points' largest
/// distance from the origin at t0) plus what the trajectory can sweep over its duration T: for
/// the rotation, T max|ω̄| (the largest rate of a body at an output, B.W1..B.W3); for the
/// points, T max(|v_WBo| + |ω̄| |p_WP − p_WBo|), a bound on a tracked point's rigid-motion
/// speed from its body's columns (B.x…, B.vx…, B.W1…), plus ‖Φ_k‖_F |q̇_f| for a point of
/// `nodes` (its elastic velocity), or the polyline through its outputs when the body's columns
/// are missing.
///
/// Why: an evaluation at t rounds the rates it computes by u relative; the error u|ω(t)| in a
/// body's rate persists and turns its attitude by up to u|ω(t)|(T − t) ≤ u T max|ω̄|, and an
/// error in a velocity moves a point by up to u T × its largest speed. Summed over the
/// evaluations without cancellation, u × evaluations × this scale bounds the round-off. The
/// maxima are sampled at the outputs. The t0 size alone did not bound it: a free
/// body spinning at 200 rad/s for 10 s in extended lay 2.0e-13 rad from quad, above the estimate
/// it gave, 1.47e-13 = 2 × 2.7e-14 (the distance to the tighter run) + u × 417 672 evaluations ×
/// (π + 1) (tests/precision/roundoff_scale_test.cpp).
///
/// For the default metric (trajectory::kDefaultMetric), whose errors are fractions of each
/// quantity's range: the rotation's scale over π plus the points' over the smallest extent of a
/// tracked point in `table`.
double roundoff_scale(const trajectory::TrajectoryTable& table, const std::string& metric,
                      std::span<const NodePoint> nodes = {});

}  // namespace flexref::precision
