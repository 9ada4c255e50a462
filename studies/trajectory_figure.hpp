#pragma once

/// \file trajectory_figure.hpp
/// The paper's trajectory figures (Figs. 1–3): the world trajectory of one tracked point
/// integrated by each scheme at a few steps, with the reference on the same axes, and the L∞
/// distance of each curve to the reference. A scheme that fails (blows up, Newton diverges)
/// keeps its curve up to the failure and says where and why: at the paper's large steps the
/// explicit schemes can be unstable, and the figure must show that rather than stop. A curve
/// whose run breaks the scene's invariants (core/invariants.hpp) is drawn in full and marked
/// unstable.

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "studies/reference_precision.hpp"
#include "trajectory/certified_reference.hpp"

namespace flexref::studies {

struct FigureSettings {
  std::vector<std::string> schemes = lie::default_scheme_names();
  /// The options every scheme's stepper is built with (genalpha's ρ∞ and perturbed start, a
  /// user method's named values; lie/method_options.hpp).
  lie::MethodOptions method_options;
  std::vector<double> steps;  ///< s
  int body = 0;
  int point = 0;                 ///< index into the body's tracked points
  std::string solver = "cvode";  ///< reference solver
  double rtol = 1e-10;
  int jobs = 1;
  bool progress = false;  ///< "figure: k/N runs" on stderr (studies/progress.hpp)
  /// A reference computed elsewhere (an extended or quad precision one: docs/precision.md),
  /// used instead of solving with `solver`; its estimate (metric "points") certifies the curves.
  std::shared_ptr<const trajectory::CertifiedReference> given_reference;
  /// The given reference's precision (for the table).
  ReferencePrecision given_precision = ReferencePrecision::kQuad;
  /// Estimate the double reference's own error (metric "points": two more reference runs) so
  /// that each curve's error can be certified (≥ 100× the estimate).
  bool estimate = true;
};

struct FigureCurve {
  std::string label;   ///< "c1 h=0.5" or "reference"
  std::string scheme;  ///< empty for the reference
  double step = 0.0;
  std::vector<double> times;
  std::vector<Eigen::Vector3d> p_W;  ///< the tracked point, world, m
  bool completed = true;
  std::string failure;  ///< where and why the run stopped, empty when completed
  /// The invariant the run broke (core::InvariantBreach::describe; the curve's label then ends
  /// in " (unstable)"), empty when it broke none.
  std::string instability;
  /// L∞ over the curve's times of |p − p_ref| (m); NaN when no time is shared.
  double max_error = 0.0;
  /// max_error ≥ 100 × the reference's estimated error (the 100× rule of docs/design/studies.md).
  bool certified = true;
};

struct FigureResult {
  FigureCurve reference;
  ReferencePrecision reference_precision = ReferencePrecision::kDouble;
  /// The reference's estimated error in the "points" metric (m): NaN when not estimated.
  double reference_estimate = std::numeric_limits<double>::quiet_NaN();
  std::string reference_estimate_method;
  std::vector<FigureCurve> curves;  ///< schemes × steps, in settings order
};

/// Integrates the reference at `output_times` and every (scheme, step). A scheme curve records
/// the point every max(1, round(output_step/h)) steps, so its times are on the reference grid
/// whenever h divides the output step or is a multiple of it. Throws std::invalid_argument for
/// unknown schemes, steps that do not land on the end time, or a body/point out of range.
FigureResult run_trajectory_figure(const core::Model& model,
                                   const std::vector<double>& output_times,
                                   const FigureSettings& settings);

/// Whether any scheme curve has an error below 100× the reference's estimated error.
bool figure_has_uncertified(const FigureResult& result);

/// Long-format CSV: curve,scheme,step,t,x,y,z (one row per recorded time and curve).
std::string figure_csv(const FigureResult& result);
/// Text table: the reference line (precision, estimated error), then scheme, step, L∞ error,
/// certified, status.
std::string figure_table(const FigureResult& result);

}  // namespace flexref::studies
