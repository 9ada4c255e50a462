#include "studies/certified_reference.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>

#include "core/output_times.hpp"
#include "scene/scene_reader.hpp"
#include "studies/study_refused.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::studies {
namespace {

TEST_CASE("solution_scale is pi plus the scene's extent at t0", "[studies][reference]") {
  // free_spin: its tracked point (1, 0, 0) on a body at the origin, so rotation+points gives
  // π + 1; "points" alone gives 1 and "rotation" π. Later rows do not count.
  const core::Model model = testing::free_spin();
  core::Trajectory trajectory;
  trajectory.times = {0.0, 1.0};
  trajectory.states = {model.initial_state(), model.initial_state()};
  trajectory.states[1][0].p_WBr.x() = 1e6;
  const TrajectoryTable table = tabulate(model, trajectory);
  CHECK(solution_scale(table, "rotation+points") == Approx(std::numbers::pi + 1.0));
  CHECK(solution_scale(table, "points") == Approx(1.0));
  CHECK(solution_scale(table, "rotation") == Approx(std::numbers::pi));
}

TEST_CASE("a reference whose error estimate exceeds the solution itself is refused",
          "[studies][reference]") {
  // spin_up_beam_6 under the coupled model: spun above its first bending frequency, the linear
  // floating-frame model diverges exponentially (docs/design/model.md) and CVODE and Odeint
  // disagree by 2.6e34 m on a 10 m beam. `flexref reference` used to report that as an
  // "estimated error" and exit 0.
  const scene::Scene scene =
      scene::read_scene("scenes/spin_up_beam_6.toml", core::FlexibleFormulation::kCoupled);
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);
  try {
    certified_reference(*scene.model, times, "cvode", {}, "rotation+points");
    FAIL("no exception");
  } catch (const StudyRefused& e) {
    CHECK(std::string(e.what()).find("certifies nothing") != std::string::npos);
  }
  // The LTE model of the same scene stays bounded: certified.
  const scene::Scene lte =
      scene::read_scene("scenes/spin_up_beam_6.toml", core::FlexibleFormulation::kLte);
  const CertifiedReference ok =
      certified_reference(*lte.model, times, "cvode", {}, "rotation+points");
  CHECK(ok.estimate.estimate() < 1e-3 * solution_scale(ok.table, "rotation+points"));
}

}  // namespace
}  // namespace flexref::studies
