#pragma once
/// \file exact_high_precision.hpp
/// The exact solutions of reference/ (torque-free body by Jacobi elliptic functions, Lagrange
/// top) evaluated in extended or quad precision (docs/precision.md): the same closed forms as
/// the double `--solver exact`, instantiated in the run's scalar type, with the principal-axes
/// decomposition in that type too, tabulated in the columns and text format of
/// solve_high_precision (per body p, θ, v, ω̄, tracked points, energy; OdeSystemTpl<S>::
/// output_row), so that precision::distance compares the two in the runs' precision.
#include <string>
#include <vector>

#include "precision/high_precision_reference.hpp"
#include "precision/precision.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::precision {

/// The exact solution of the scene at output_times in `precision` (kDouble, kExtended or
/// kQuad). The scene must be one reference::classify_exact_solution calls "torque_free" (one
/// free body, no load) or "heavy_top" (one symmetric pivot body, gravity only, centre of mass
/// on the symmetry axis).
/// \throws std::invalid_argument naming the reason otherwise (no exact solution, or the
/// compound pendulum, whose exact solution is double only).
HighPrecisionRun exact_high_precision(const scene::SceneSpec& spec,
                                      const std::vector<double>& output_times, Precision precision);

/// The error estimate of an exact run (exact_high_precision), made as the double exact
/// reference's (trajectory/certified_reference.hpp): the distance, in `metric` and computed in the
/// run's precision, to an independent numerical solution in the same precision (Bulirsch–Stoer
/// at smallest_rtol, its tightest tolerance). It bounds the exact solution's error plus the
/// numerical one's. A distance of exactly 0 is no check: the estimate is then +inf (unknown).
/// `progress` (may be null) follows the numerical solve. Throws as solve_high_precision.
trajectory::ReferenceEstimate exact_high_precision_estimate(
    const scene::SceneSpec& spec, const std::vector<double>& output_times,
    const HighPrecisionRun& exact, const std::string& metric,
    reference::SolveProgress* progress = nullptr);

}  // namespace flexref::precision
