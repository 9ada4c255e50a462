/// \file contact_reference_cost_study_test.cpp
/// The table of docs/contact_results.md, "Reference cost at an estimated error ≤ 1e-6": for
/// each contact scene and reference solver, the estimated error at a range of tolerances (L∞
/// over the 0.01 s outputs of frame-origin position (m) plus geodesic angle (rad), against a
/// run at 100× tighter rtol) and the cost. Label `study` (~25 s of CPU): every solve must
/// succeed, every contact onset must have its release, and the tightest tolerance tried must
/// reach the documented 1e-6 wherever the document says it does. `-s` shows the table.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/output_times.hpp"
#include "reference/reference_solver.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/contact_models.hpp"

namespace flexref {
namespace {

using reference::ReferenceRun;
using reference::SolverOptions;

/// L∞ over the outputs and bodies of the frame-origin distance plus the geodesic angle.
double position_and_angle_distance(const core::Model& model, const core::Trajectory& a,
                                   const core::Trajectory& b) {
  double distance = 0.0;
  for (std::size_t i = 0; i < a.times.size(); ++i) {
    double position = 0.0, angle = 0.0;
    for (int body = 0; body < model.num_bodies(); ++body) {
      const auto k = static_cast<std::size_t>(body);
      position = std::max(
          position, (model.p_WBo(body, a.states[i][k]) - model.p_WBo(body, b.states[i][k])).norm());
      angle = std::max(angle,
                       rotation::geodesic_angle(a.states[i][k].theta_WB, b.states[i][k].theta_WB));
    }
    distance = std::max(distance, position + angle);
  }
  return distance;
}

}  // namespace

TEST_CASE("contact scenes: reference error estimates and cost", "[contact][table]") {
  using Solve =
      ReferenceRun (*)(const core::Model&, const std::vector<double>&, const SolverOptions&);
  const std::vector<std::pair<std::string, Solve>> solvers = {{"cvode", &reference::solve_cvode},
                                                              {"odeint", &reference::solve_odeint}};
  std::vector<testing::ContactScene> scenes = testing::all_contact_scenes();
  scenes.push_back(testing::double_pendulum_impacts(3.0));
  scenes.push_back(testing::double_pendulum_impacts(1.0));
  for (testing::ContactScene& scene : scenes) {
    const std::vector<double> times = core::output_times(scene.end_time, 0.01);
    for (const auto& [solver, solve] : solvers) {
      std::vector<double> rtols = {1e-7, 1e-8, 1e-9, 1e-10};
      if (solver == "cvode" && (scene.name == "tippe_top" || scene.end_time <= 3.0)) {
        rtols = {1e-11, 1e-12};  // CVODE needs these here (its 1e-7…1e-10 rows: the doc)
      }
      // Where the document finds no tolerance that reaches 1e-6: the double pendulum over its
      // 10 s is chaotic (runs 100× apart differ by O(1) m); CVODE's BDF on the 180 rad/s tippe
      // top (2.9e-4 at 1e-12) and on the 3 s double pendulum's ringing joints (1.2e-6 at 1e-12).
      const bool documented_target =
          !(scene.name == "double_pendulum_impacts" && scene.end_time > 3.0) &&
          !(solver == "cvode" && (scene.name == "tippe_top" || scene.end_time == 3.0));
      double error = 0.0;
      for (double rtol : rtols) {
        // A solver failure is an exception here and fails the test.
        const ReferenceRun run = solve(scene.model, times, SolverOptions{rtol, -1.0});
        const ReferenceRun tight = solve(scene.model, times, SolverOptions{rtol / 100.0, -1.0});
        error = position_and_angle_distance(scene.model, run.trajectory, tight.trajectory);
        INFO("TABLE " << scene.name << " end " << scene.end_time << " " << solver << " rtol "
                      << rtol << " est " << error << " cpu " << run.stats.cpu_seconds << " steps "
                      << run.stats.steps << " events " << run.stats.events);
        CHECK(std::isfinite(error));
        CHECK(run.event_times.size() % 2 == 0);  // every onset has its release
      }
      if (documented_target) {
        INFO(scene.name << " (" << scene.end_time << " s) " << solver << " at rtol " << rtols.back()
                        << ": estimate " << error);
        CHECK(error <= 1e-6);
      }
    }
  }
}

}  // namespace flexref
