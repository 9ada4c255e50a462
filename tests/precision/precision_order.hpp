#pragma once
/// \file precision_order.hpp
/// The ordering check of references in three precisions, shared by the unit test (short
/// horizons) and the study test (whole scenes).
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "precision/high_precision_reference.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::precision {

inline scene::SceneSpec spec_of(const std::string& file) { return scene::read_scene(file).spec; }

/// The rigid bundled scenes whose quad references take seconds over their whole horizon (the
/// stiff joint and contact scenes take 12-40 s per simulated second, kSustainedContactScenes and
/// double_pendulum_impacts: short horizons in the unit label, whole ones in the study label).
inline constexpr const char* kFastRigidScenes[] = {
    "scenes/free_spin.toml",     "scenes/book_toss.toml",   "scenes/book_toss_step.toml",
    "scenes/heavy_top.toml",     "scenes/pendulum.toml",    "scenes/bouncing_ball.toml",
    "scenes/sliding_block.toml", "scenes/coulomb_wall.toml"};

/// The rigid bundled scenes whose contacts or joints stay loaded, checked over short horizons:
/// quad resolves their stiff contact and joint modes at 25-40 s per simulated second on one core
/// (docs/precision.md, "Not yet").
inline constexpr const char* kSustainedContactScenes[] = {
    "scenes/top_on_plane.toml", "scenes/tippe_top.toml", "scenes/pendulum_on_sliding_support.toml"};

/// The bundled scenes with a flexible body whose references take minutes over their whole
/// horizon (all but flexible_spinner_64, whose top mode at 1.8e4 rad/s must be
/// resolved in quad for hours, checked over 20 ms, and tube_support_impact, checked over shorter
/// horizons for its 1625 impacts: docs/precision.md).
inline constexpr const char* kFlexibleScenes[] = {
    "scenes/flexible_spinner.toml",     "scenes/hinged_spinner_strike.toml",
    "scenes/rotating_cantilever.toml",  "scenes/rotating_cantilever_stiff.toml",
    "scenes/spin_up_beam.toml",         "scenes/spin_up_beam_4.toml",
    "scenes/spin_up_beam_6.toml",       "scenes/spin_up_beam_stiff_2.toml",
    "scenes/spin_up_beam_stiff_4.toml", "scenes/spin_up_beam_stiff_6.toml",
    "scenes/spin_up_beam_stiff_10.toml"};

/// The index of column `name` in a run's text rows (which have no `t`); fails the test when the
/// run has no such column.
inline std::size_t column(const HighPrecisionRun& run, const std::string& name) {
  for (std::size_t c = 1; c < run.columns.size(); ++c) {
    if (run.columns[c] == name) return c - 1;
  }
  FAIL("no column " << name);
  return 0;
}

/// Quad, extended and double (CVODE rtol 1e-12) references of a scene up to `end_time` agree in
/// that order: the extended reference is within its own estimate of quad, the double one within
/// its estimate, and quad's estimate is below the extended reference's distance to it.
inline void check_precision_order(
    scene::SceneSpec spec, double end_time,
    core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled) {
  CAPTURE(spec.name);
  CAPTURE(core::to_string(formulation));
  spec.end_time = std::min(spec.end_time, end_time);
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  HighPrecisionRun quad, ext;
  const trajectory::CertifiedReference q = certified_high_precision_reference(
      spec, times, Precision::kQuad, 1e-26, "rotation+points", &quad, formulation);
  const trajectory::CertifiedReference e = certified_high_precision_reference(
      spec, times, Precision::kExtended, 1e-16, "rotation+points", &ext, formulation);
  const double ext_vs_quad = distance(ext, quad, "rotation+points");
  INFO("quad estimate " << q.estimate.value << ", extended estimate " << e.estimate.value
                        << ", extended vs quad " << ext_vs_quad);
  CHECK(q.estimate.value < 1e-20);
  CHECK(std::isfinite(e.estimate.value));  // an estimate, not "none: no usable check"
  CHECK(ext_vs_quad <= e.estimate.value);
  CHECK(q.estimate.value < ext_vs_quad);
  const core::Model model = scene::build_model(spec, formulation);
  reference::SolverOptions o;
  o.rtol = 1e-12;
  const trajectory::CertifiedReference d = trajectory::certified_reference(
      model, times, "cvode", o, "rotation+points", {.use_exact_solution = false});
  const double double_vs_quad = trajectory::metric_value(
      trajectory::compare_trajectories(d.table, q.table), "rotation+points");
  INFO("double estimate " << d.estimate.value << ", double vs quad " << double_vs_quad);
  CHECK(double_vs_quad <= d.estimate.value);
  CHECK(ext_vs_quad < double_vs_quad);
}

/// The same for a bundled scene file.
inline void check_precision_order(
    const std::string& file, double end_time,
    core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled) {
  CAPTURE(file);
  check_precision_order(spec_of(file), end_time, formulation);
}

}  // namespace flexref::precision
