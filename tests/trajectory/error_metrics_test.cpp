#include "trajectory/error_metrics.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "tests/support/flexible_models.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {
namespace {

TEST_CASE("the modes metric is the L-infinity modal-coordinate error", "[studies][metrics]") {
  Eigen::VectorXd q0(2);
  q0 << 0.02, 0.01;
  const core::Model model =
      testing::rotating_cantilever_model(core::FlexibleFormulation::kCoupled, 3.0, 2, 10, q0);
  core::Trajectory reference;
  for (int k = 0; k < 4; ++k) {
    core::State s = model.initial_state();
    model.apply_prescribed_motion(0.1 * k, s);
    reference.times.push_back(0.1 * k);
    reference.states.push_back(s);
  }
  core::Trajectory run = reference;
  // Perturb q2 by 3e-4 at the third output and q1 by 1e-4 at the last.
  run.states[2][0].q_f(1) += 3e-4;
  run.states[3][0].q_f(0) -= 1e-4;
  const ComparisonReport report =
      compare_trajectories(tabulate(model, run), tabulate(model, reference));
  // CSV values are written with 17 digits: the difference is exact to ~1e-17.
  CHECK(metric_value(report, "modes") == Approx(3e-4).epsilon(1e-12));
  // The tip moves with q: the points metric sees the perturbation too, the rotation does not.
  CHECK(metric_value(report, "points") > 0.0);
  CHECK(metric_value(report, "rotation") == 0.0);
  CHECK_THROWS_AS(metric_value(report, "modal"), std::invalid_argument);
}

TEST_CASE("a metric with nothing to measure is an error, never 0", "[studies][metrics]") {
  // A rigid scene has no modal coordinates: "modes" would otherwise report a perfect 0.
  const ComparisonReport empty;
  CHECK_THROWS_WITH(metric_value(empty, "modes"), Catch::Matchers::Contains("nothing to measure"));
  CHECK_THROWS_WITH(metric_value(empty, "rotation+points"),
                    Catch::Matchers::Contains("nothing to measure"));
  CHECK_THROWS_WITH(metric_value(empty, kDefaultMetric),
                    Catch::Matchers::Contains("nothing to measure"));
}

/// Body b turning about z through a full circle (φ = 0, π/2, π, 3π/2, 2π) about the world
/// origin, its point p at `radius` on its x axis: the point's extent is 2 radius exactly (the
/// bounding box of the five positions is centred on the origin). The run (`run` true) is turned
/// a further `angle` about z at every time and its point moved `shift` along z.
TrajectoryTable turning_body(double radius, bool run, double angle, double shift) {
  TrajectoryTable table;
  table.columns = {"t", "b.e0", "b.e1", "b.e2", "b.e3", "b.p.x", "b.p.y", "b.p.z"};
  for (int k = 0; k <= 4; ++k) {
    const double phi = 0.5 * std::numbers::pi * k + (run ? angle : 0.0);
    table.rows.push_back({0.1 * k, std::cos(0.5 * phi), 0.0, 0.0, std::sin(0.5 * phi),
                          radius * std::cos(0.5 * std::numbers::pi * k),
                          radius * std::sin(0.5 * std::numbers::pi * k), run ? shift : 0.0});
  }
  return table;
}

TEST_CASE("the default metric is dimensionless: each quantity over its range, the largest",
          "[studies][metrics]") {
  // Rotation error 1e-3 rad (range π), point error 2e-4 m (range 1 m, radius 0.5 m): the
  // fractions 3.18e-4 and 2e-4, the larger taken.
  const double angle = 1e-3;
  const ComparisonReport m =
      compare_trajectories(turning_body(0.5, true, angle, 2e-4), turning_body(0.5, false, 0, 0));
  // Tolerance: the geodesic angle of two unit quaternions 1e-3 apart is exact to a few ε
  // relative (atan2 of a difference of products, ~1e-16 absolute on 1e-3: 1e-13 relative),
  // the shift 2e-4 is a difference of two doubles (exact); 1e-9 is far above both.
  CHECK(metric_value(m, kDefaultMetric) == Approx(angle / std::numbers::pi).epsilon(1e-9));
  CHECK(metric_value(m, "rotation+points") == Approx(angle + 2e-4).epsilon(1e-9));
  CHECK(metric_unit(kDefaultMetric) == "1");
  CHECK(metric_unit("rotation+points") == "rad + m");
  CHECK(metric_terms(m, kDefaultMetric) == "largest of b.rotation / pi rad, b.p / 1 m");
  // The point's fraction when it is the larger: 5e-4 m over 1 m, not the sum of the two (8.2e-4).
  const ComparisonReport p =
      compare_trajectories(turning_body(0.5, true, angle, 5e-4), turning_body(0.5, false, 0, 0));
  CHECK(metric_value(p, kDefaultMetric) == Approx(5e-4).epsilon(1e-9));

  // The same motion in millimetres: the default metric is unchanged (it never adds radians to
  // a length), where rotation+points grows by the point's 0.2 (its error now 0.2 "mm").
  const ComparisonReport mm =
      compare_trajectories(turning_body(500.0, true, angle, 0.2), turning_body(500.0, false, 0, 0));
  // Tolerance: the two differ only by the rounding of positions 1000× larger (a few ε).
  CHECK(metric_value(mm, kDefaultMetric) == Approx(metric_value(m, kDefaultMetric)).epsilon(1e-12));
  CHECK(metric_value(p, kDefaultMetric) ==
        Approx(metric_value(compare_trajectories(turning_body(500.0, true, angle, 0.5),
                                                 turning_body(500.0, false, 0, 0)),
                            kDefaultMetric))
            .epsilon(1e-12));
  CHECK(metric_value(mm, "rotation+points") == Approx(angle + 0.2).epsilon(1e-9));
  CHECK(metric_terms(mm, kDefaultMetric) == "largest of b.rotation / pi rad, b.p / 1e+03 m");

  // A point the reference holds still has no range: refused by name, never a fraction of 0.
  const ComparisonReport still =
      compare_trajectories(turning_body(0.0, true, angle, 1e-4), turning_body(0.0, false, 0, 0));
  CHECK_THROWS_WITH(metric_value(still, kDefaultMetric),
                    Catch::Matchers::Contains("cannot scale b.p"));
  CHECK(metric_value(still, "points") == Approx(1e-4).epsilon(1e-12));
}

/// A table with one body's position columns only.
TrajectoryTable positions_only() {
  TrajectoryTable table;
  table.columns = {"t", "b.x", "b.y", "b.z"};
  table.rows = {{0.0, 1, 2, 3}, {0.1, 1, 2, 3}};
  return table;
}

TEST_CASE("joint metrics: reaction force and torque errors, the run's own violation",
          "[studies][metrics][joints]") {
  // A joint J's columns (docs/output.md, "Joints") over three times; the run is off the
  // reference by (3, 4, 0) N in force at the second time and by (0, 0, 2) N*m in torque at the
  // third, and has left the constraint by Φ = -5e-7 at the second time (the reference by 1e-15).
  TrajectoryTable reference;
  reference.columns = {"t", "J.fx", "J.fy", "J.fz", "J.tx", "J.ty", "J.tz", "J.phi", "J.phi_dot"};
  reference.rows = {{0.0, 10, 20, 30, 1, 2, 3, 0.0, 0.0},
                    {0.1, 11, 21, 31, 1, 2, 3, 1e-15, 0.0},
                    {0.2, 12, 22, 32, 1, 2, 3, 0.0, 0.0}};
  TrajectoryTable run = reference;
  run.rows[1][1] += 3.0;
  run.rows[1][2] += 4.0;
  run.rows[2][6] -= 2.0;
  run.rows[1][7] = -5e-7;
  const ComparisonReport report = compare_trajectories(run, reference);
  // Sums and differences of small integers are exact in double: |(3, 4, 0)| = 5 exactly.
  CHECK(metric_value(report, "reaction_force") == 5.0);
  CHECK(metric_value(report, "reaction_torque") == 2.0);
  // The run's own |Φ|, not its difference to the reference's 1e-15: exactly 5e-7.
  CHECK(metric_value(report, "violation") == 5e-7);
  // Without joint columns the joint metrics have nothing to measure (never a silent 0).
  CHECK_THROWS_WITH(
      metric_value(compare_trajectories(positions_only(), positions_only()), "reaction_force"),
      Catch::Matchers::Contains("J.fx..J.fz"));
}

/// A body's position columns b.x, b.y, b.z over `rows` times, every row at `position`.
TrajectoryTable positions(double position, int rows) {
  TrajectoryTable table;
  table.columns = {"t", "b.x", "b.y", "b.z"};
  for (int k = 0; k < rows; ++k) {
    table.rows.push_back({0.1 * k, position, position, position});
  }
  return table;
}

TEST_CASE("the norms neither overflow nor underflow where the error is representable",
          "[studies][metrics]") {
  // |(d, d, d)| = √3 d over every row: L∞, RMS and final value are all √3 d. The squares of
  // 1e200 (1e400) overflow and those of 1e-200 (1e-400) underflow double precision; the
  // scaled norms are accurate to a few roundings (4 ε, relative).
  constexpr double kRoundings = 4.0 * std::numeric_limits<double>::epsilon();
  for (const double d : {1e200, 1e-200, 1.0}) {
    INFO("d = " << d);
    const ComparisonReport report = compare_trajectories(positions(d, 5), positions(0.0, 5));
    REQUIRE(report.quantities.size() == 1);
    const ErrorNorms& n = report.quantities.front().norms;
    const double expected = std::sqrt(3.0) * d;
    CHECK(std::abs(n.linf - expected) <= kRoundings * expected);
    CHECK(std::abs(n.rms - expected) <= kRoundings * expected);
    CHECK(std::abs(n.final - expected) <= kRoundings * expected);
  }
  // A difference beyond double precision itself (1e308 − (−1e308)) stays infinite.
  const ComparisonReport report = compare_trajectories(positions(1e308, 2), positions(-1e308, 2));
  CHECK(std::isinf(report.quantities.front().norms.linf));
  CHECK(std::isinf(report.quantities.front().norms.rms));
}

}  // namespace
}  // namespace flexref::trajectory
