/// \file reduced_cvode_study_test.cpp
/// The reduced reference (reference/reduced_cvode.hpp) against the maximal CVODE reference on
/// every bundled scene of rigid bodies on ideal joints without contact, over each scene's whole
/// horizon at rtol 1e-10 (a study: label `study`, not run by CI; docs/reduced_coordinates.md has
/// its figures): the largest difference of the bodies' attitudes (geodesic angle) and of their
/// positions relative to the joints' length scale, over all output times, and both runs' CPU.
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::reference {
namespace {

TEST_CASE("reduced cvode study: the bundled jointed scenes against the maximal reference",
          "[reduced][study]") {
  const double rtol = 1e-10;
  for (const char* name : {"andrews_squeezer", "four_bar", "bricard", "double_pendulum_ideal",
                           "heavy_top_spherical", "slider_crank"}) {
    const scene::Scene scene = scene::read_scene(std::string("scenes/") + name + ".toml");
    const core::Model& model = *scene.model;
    const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);
    SolverOptions options;
    options.rtol = rtol;
    const auto t0 = std::chrono::steady_clock::now();
    options.coordinates = Coordinates::kMaximal;
    const ReferenceRun maximal = solve_reference("cvode", model, times, options);
    const auto t1 = std::chrono::steady_clock::now();
    options.coordinates = Coordinates::kJoint;
    const ReferenceRun run = solve_reference("cvode", model, times, options);
    const auto t2 = std::chrono::steady_clock::now();
    double angle = 0.0, position = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      for (int b = 0; b < model.num_bodies(); ++b) {
        const auto i = static_cast<std::size_t>(b);
        const core::BodyState& x = maximal.trajectory.states[k][i];
        const core::BodyState& y = run.trajectory.states[k][i];
        angle = std::max(angle, rotation::geodesic_angle(x.theta_WB, y.theta_WB));
        position = std::max(position, (x.p_WBr - y.p_WBr).norm() / model.joint_length_scale());
      }
    }
    const double maximal_s = std::chrono::duration<double>(t1 - t0).count();
    const double reduced_s = std::chrono::duration<double>(t2 - t1).count();
    std::printf(
        "%-22s maximal %5ld steps %8.2f ms, reduced %5ld steps %8.2f ms: "
        "attitude %.2e rad, position %.2e of l\n",
        name, maximal.stats.steps, 1e3 * maximal_s, run.stats.steps, 1e3 * reduced_s, angle,
        position);
    // Both promise rtol per radian turned (or per unit length): the most any body turns here
    // is the heavy top's 300 rad (150 rad/s for 2 s), so each is within 300 rtol and their
    // difference within 600 rtol; 1e3 rtol leaves a factor of 1.7 (the other scenes turn at
    // most 16 rad, Andrews' K1, and sit far below).
    CHECK(angle <= 1e3 * rtol);
    CHECK(position <= 1e3 * rtol);
  }
}

}  // namespace
}  // namespace flexref::reference
