/// \file roundoff_scale_test.cpp
/// The round-off part of an extended or quad reference's estimate (precision/roundoff_scale.hpp):
/// the swept angle and paths on a table built by hand, and the estimate of a fast spin in
/// extended against the exact torque-free solution in quad.
#include "precision/roundoff_scale.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "precision/exact_high_precision.hpp"
#include "precision/high_precision_reference.hpp"
#include "precision/precision.hpp"
#include "studies/certified_reference.hpp"
#include "tests/precision/precision_order.hpp"

namespace flexref::precision {
namespace {

TEST_CASE("roundoff_scale adds the swept angle and the longest path", "[precision]") {
  // A body turning at |ω̄| = 5 rad/s for 2 s (10 rad) whose point p goes (1,0,0) → (1,2,0) →
  // (1,2,2) (a 4 m path); its origin b.x… moves 30 m, which is no tracked point.
  studies::TrajectoryTable table;
  table.columns = {"t",    "b.x",  "b.y",  "b.z",  "b.e0",  "b.e1",  "b.e2",
                   "b.e3", "b.W1", "b.W2", "b.W3", "b.p.x", "b.p.y", "b.p.z"};
  table.rows = {{0.0, 0.0, 0, 0, 1, 0, 0, 0, 3.0, 4.0, 0.0, 1.0, 0.0, 0.0},
                {1.0, 10.0, 0, 0, 1, 0, 0, 0, 0.0, 3.0, 4.0, 1.0, 2.0, 0.0},
                {2.0, 30.0, 0, 0, 1, 0, 0, 0, 4.0, 0.0, -3.0, 1.0, 2.0, 2.0}};
  // solution_scale: π for the rotation, |p(0)| = 1 m for the points.
  CHECK(roundoff_scale(table, "rotation") == Approx(std::numbers::pi + 10.0));
  CHECK(roundoff_scale(table, "points") == Approx(1.0 + 4.0));
  CHECK(roundoff_scale(table, "rotation+points") == Approx(std::numbers::pi + 1.0 + 10.0 + 4.0));
}

TEST_CASE("the extended estimate bounds a fast spin's round-off", "[precision]") {
  // free_spin's body (J = diag(3, 4, 5)) at ω̄0 = (2, 3, 200) rad/s for 10 s, outputs every
  // 10 ms: extended at rtol 1e-16 lies 2.0e-13 rad from the exact solution (quad), mostly
  // round-off that the tighter extended check shares (2 × its distance: 1.5e-13). The bound
  // with the t0 extent alone, u × 417 672 evaluations × (π + 1) = 9.3e-14, left the estimate
  // (1.47e-13) below the error; the swept angle (~2000 rad) makes it 8.4e-11, honest and 420×
  // loose.
  scene::SceneSpec spec = spec_of("scenes/free_spin.toml");
  spec.end_time = 10.0;
  spec.output_step = 0.01;
  spec.bodies[0].description.initial.w_WB_B = Eigen::Vector3d(2.0, 3.0, 200.0);
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun exact = exact_high_precision(spec, times, Precision::kQuad);
  HighPrecisionRun ext;
  const studies::CertifiedReference e = certified_high_precision_reference(
      spec, times, Precision::kExtended, 1e-16, "rotation+points", &ext);
  const double error = distance(ext, exact, "rotation+points");
  REQUIRE(e.estimate.checks.size() == 1);
  const double old_bound = 2.0 * e.estimate.checks[0].distance +
                           unit_roundoff(Precision::kExtended) *
                               static_cast<double>(ext.evaluations) *
                               studies::solution_scale(ext.table, "rotation+points");
  INFO("error " << error << ", estimate " << e.estimate.value << ", t0-extent bound " << old_bound);
  CHECK(error <= e.estimate.value);
  // The case still tells the two bounds apart (else it no longer guards the sweep term).
  CHECK(old_bound < error);
}

}  // namespace
}  // namespace flexref::precision
