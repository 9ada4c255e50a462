#pragma once

/// \file trajectory_figure.hpp
/// The paper's trajectory figures (Figs. 1–3): the world trajectory of one tracked point
/// integrated by each scheme at a few steps, with the reference on the same axes, and the L∞
/// distance of each curve to the reference. A scheme that fails (blows up, Newton diverges)
/// keeps its curve up to the failure and says where and why: at the paper's large steps the
/// explicit schemes can be unstable, and the figure must show that rather than stop.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/stepper.hpp"

namespace flexref::studies {

struct FigureSettings {
  std::vector<std::string> schemes = lie::scheme_names();
  std::vector<double> steps;  ///< s
  int body = 0;
  int point = 0;                 ///< index into the body's tracked points
  std::string solver = "cvode";  ///< reference solver
  double rtol = 1e-10;
  int jobs = 1;
  bool progress = false;  ///< "figure: k/N runs" on stderr (studies/progress.hpp)
};

struct FigureCurve {
  std::string label;   ///< "c1 h=0.5" or "reference"
  std::string scheme;  ///< empty for the reference
  double step = 0.0;
  std::vector<double> times;
  std::vector<Eigen::Vector3d> p_W;  ///< the tracked point, world, m
  bool completed = true;
  std::string failure;  ///< where and why the run stopped, empty when completed
  /// L∞ over the curve's times of |p − p_ref| (m); NaN when no time is shared.
  double max_error = 0.0;
};

struct FigureResult {
  FigureCurve reference;
  std::vector<FigureCurve> curves;  ///< schemes × steps, in settings order
};

/// Integrates the reference at `output_times` and every (scheme, step). A scheme curve records
/// the point every max(1, round(output_step/h)) steps, so its times are on the reference grid
/// whenever h divides the output step or is a multiple of it. Throws std::invalid_argument for
/// unknown schemes, steps that do not land on the end time, or a body/point out of range.
FigureResult run_trajectory_figure(const core::Model& model,
                                   const std::vector<double>& output_times,
                                   const FigureSettings& settings);

/// Long-format CSV: curve,scheme,step,t,x,y,z (one row per recorded time and curve).
std::string figure_csv(const FigureResult& result);
/// Text table: scheme, step, L∞ error, status.
std::string figure_table(const FigureResult& result);

}  // namespace flexref::studies
