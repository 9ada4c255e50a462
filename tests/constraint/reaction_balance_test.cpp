/// \file reaction_balance_test.cpp
/// The joints' reactions as a reference's output table writes them (`J.fx … J.tz`) against each
/// body's Newton–Euler balance, with the accelerations from the output's velocities by finite
/// differences and the force elements' loads (tests/support/newton_euler_balance.hpp): nothing
/// of the constrained solve that produced the reactions enters the balance. On the bundled
/// mechanisms (the four-bar's, over its 2 s with the re-selection of its rows at t ≈ 1.85 s, is
/// in mechanism_scenes_test.cpp) and the joint-kind scenes of tests/support/joint_kind_scenes.hpp
/// without a drive law (whose jerk jumps at the end of its spin-up, where the differences are
/// first order), every output row.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/joint_kind_scenes.hpp"
#include "tests/support/newton_euler_balance.hpp"
#include "tests/support/solver_options.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::constraint {
namespace {

struct BalanceCase {
  std::string scene;    ///< a bundled scene, or the kind of a joint-kind scene
  double horizon;       ///< s
  double step;          ///< the output grid's step h (s)
  double fastest_rate;  ///< ω, the motion's fastest rate (1/s), for (hω)⁴
};

/// Runs CVODE at rtol on the grid and returns the balance's largest relative residuals.
testing::NewtonEulerResidual balance_of(const core::Model& model, const BalanceCase& c,
                                        double rtol) {
  const std::vector<double> times = core::output_times(c.horizon, c.step);
  const reference::ReferenceRun run =
      reference::solve_reference("cvode", model, times, testing::with_rtol(rtol));
  const trajectory::TrajectoryTable table = trajectory::tabulate(model, run.trajectory);
  return testing::newton_euler_residual(model, run.trajectory, table);
}

void check_balance(const testing::NewtonEulerResidual& r, const BalanceCase& c, double rtol) {
  INFO(c.scene << " over " << c.horizon << " s, h = " << c.step << ": force residual " << r.force
               << " (" << r.force_at << "), torque residual " << r.torque << " (" << r.torque_at
               << ")");
  CHECK(r.rows == core::output_times(c.horizon, c.step).size());
  // The residual is the differences' error relative to the balance's largest term: truncation
  // ≤ (hω)⁴/5 (one-sided stencils; the grids below keep hω ≤ 0.03, so ≤ 2e-7) plus the
  // velocities' noise, ≤ 10.7 × (the solver's local error, ~10 rtol relative) / (hω), with
  // hω ≥ 0.01 ≤ 1e-6 at rtol 1e-10 — 1e-5 bounds both with a margin of 5. A reaction with a
  // wrong sign, point or row is wrong by O(1) of the balance.
  const double bound =
      std::pow(c.step * c.fastest_rate, 4) / 5.0 + 10.7 * 10.0 * rtol / (c.step * c.fastest_rate);
  INFO("truncation and noise bound " << bound);
  CHECK(bound <= 2e-6);
  CHECK(r.force <= 1e-5);
  CHECK(r.torque <= 1e-5);
}

/// A bundled scene's balance at rtol 1e-10 over [0, c.horizon].
void check_bundled_balance(const BalanceCase& c) {
  const double rtol = 1e-10;
  const scene::Scene scene = scene::read_scene("scenes/" + c.scene + ".toml");
  check_balance(balance_of(*scene.model, c, rtol), c, rtol);
}

// The rates: the slider-crank's crank 150 rad/s; Andrews' K1 up to ~1.4e3 rad/s; the double
// pendulum's and Bricard's links ≲ 8 and 3 rad/s (the largest |ω̄| on the grids).

TEST_CASE("reactions balance Newton-Euler's equations: slider-crank", "[constraint][reactions]") {
  check_bundled_balance({"slider_crank", 0.1, 1e-4, 150.0});
}

TEST_CASE("reactions balance Newton-Euler's equations: Andrews' squeezer",
          "[constraint][reactions]") {
  check_bundled_balance({"andrews_squeezer", 0.01, 1e-5, 1.4e3});
}

TEST_CASE("reactions balance Newton-Euler's equations: double pendulum",
          "[constraint][reactions]") {
  check_bundled_balance({"double_pendulum_ideal", 0.5, 2e-3, 8.0});
}

TEST_CASE("reactions balance Newton-Euler's equations: Bricard mechanism",
          "[constraint][reactions]") {
  check_bundled_balance({"bricard", 1.0, 5e-3, 3.0});
}

TEST_CASE("reactions balance each body's Newton-Euler equations on the joint-kind scenes",
          "[constraint][reactions]") {
  const double rtol = 1e-10;
  for (const testing::JointKindScene& kind : testing::joint_kind_scenes()) {
    const scene::Scene scene = scene::parse_scene(kind.toml, kind.kind + ".toml");
    if (!scene.model->discontinuities().empty()) continue;  // a drive's spin-up
    // The grid resolves the motion's fastest rate at hω ≤ 0.02, with the horizon on it.
    const double horizon = 1.0;
    const BalanceCase c{kind.kind, horizon, horizon / std::ceil(horizon * kind.rate / 0.02),
                        kind.rate};
    check_balance(balance_of(*scene.model, c, rtol), c, rtol);
  }
}

}  // namespace
}  // namespace flexref::constraint
