/// External levels of a scene with ideal joints (studies/convergence.hpp, "off-joints"): a run
/// that follows the mechanism with an error of order 2 is fitted at 2 with its joints at the
/// reference's own violation; the same run with a joint pulled apart by a fixed distance is off
/// its joints at every level, left out of the fit, and the note names the joint.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "studies/convergence.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {
namespace {

/// The reference's bodies turned rigidly by angle c h² about the pivot's axis z (a second-order
/// error that keeps every joint), rod2 then moved by `pull` along x, as a run in memory with the
/// bodies' pose columns only.
ExternalLevel turned_run(const trajectory::TrajectoryTable& reference, double h, double pull) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(10.0 * h * h, Eigen::Vector3d::UnitZ()));
  std::vector<std::string> names{"t"};
  for (const char* body : {"rod1", "rod2"}) {
    for (const char* c : {".x", ".y", ".z", ".e0", ".e1", ".e2", ".e3"}) {
      names.push_back(body + std::string(c));
    }
  }
  std::vector<std::vector<double>> columns(names.size());
  for (const auto& row : reference.rows) {
    columns[0].push_back(row[0]);
    for (std::size_t b = 0; b < 2; ++b) {
      const std::string body = b == 0 ? "rod1" : "rod2";
      const auto x = static_cast<std::size_t>(reference.column(body + ".x"));
      const auto e = static_cast<std::size_t>(reference.column(body + ".e0"));
      Eigen::Vector3d p = q * Eigen::Vector3d(row[x], row[x + 1], row[x + 2]);
      if (b == 1) p.x() += pull;
      const Eigen::Quaterniond a =
          q * Eigen::Quaterniond(row[e], row[e + 1], row[e + 2], row[e + 3]);
      const double values[7] = {p.x(), p.y(), p.z(), a.w(), a.x(), a.y(), a.z()};
      for (std::size_t k = 0; k < 7; ++k) columns[1 + 7 * b + k].push_back(values[k]);
    }
  }
  return {trajectory::run_from_columns("turned", names, columns), 0.0};
}

TEST_CASE("external levels off their joints are marked and left out of the fit",
          "[studies][convergence]") {
  const scene::Scene scene = scene::read_scene("scenes/double_pendulum_ideal.toml");
  const core::Model& model = *scene.model;
  const std::vector<double> times = core::output_times(0.1, 0.02);
  reference::SolverOptions solver;
  solver.rtol = 1e-12;
  const trajectory::TrajectoryTable reference = trajectory::tabulate(
      model, reference::solve_reference("cvode", model, times, solver).trajectory);

  ConvergenceOptions options;
  options.schemes = {};
  options.metric = "rotation";  // the runs have no point columns
  options.h0 = 0.02;
  options.levels = 4;
  options.reference_solver = "cvode";
  options.reference_rtol = 1e-12;
  // Errors 10 h² = 4e-3 … 6.25e-5 rad, far above the reference's (~1e-10). Joint E's error
  // scale is about 3 × 10 h² m + the pull (ρ = 1 m for both rods): a pull of 2e-3 m is 14 % of
  // it at h = 0.02 and 91 % at h = 0.0025, above 0.067 at every level; the intact run keeps E at
  // the reference's own drift.
  for (const double pull : {0.0, 2e-3}) {
    ExternalMethod method;
    method.label = pull == 0.0 ? "intact" : "pulled";
    method.claimed_order = 2;
    method.run = [&reference, pull](double h, int) { return turned_run(reference, h, pull); };
    options.external.push_back(method);
  }
  const ConvergenceResult r = run_convergence(model, times, options);
  REQUIRE(r.levels.size() == 8);
  CHECK(r.joints);
  for (std::size_t l = 0; l < 4; ++l) {
    const ConvergenceLevel& intact = r.levels[l];
    const ConvergenceLevel& pulled = r.levels[4 + l];
    INFO("h = " << intact.h << ": " << intact.joints << " | " << pulled.joints);
    CHECK(intact.status == "ok");
    // CVODE at rtol 1e-12 keeps the joints within 1e-9 m (trajectory/joint_violation_test).
    CHECK(intact.violation <= 1e-9);
    CHECK(pulled.status == "off-joints");
    CHECK(std::abs(pulled.violation - 2e-3) <= 1e-9);
    CHECK_THAT(pulled.joints, Catch::Matchers::Contains("E 0.002 m"));
  }
  REQUIRE(r.summaries.size() == 2);
  // 10 h² exactly: the fitted order is 2 to the rounding of the geodesic angle.
  CHECK(std::abs(r.summaries[0].fitted_order - 2.0) <= 1e-6);
  CHECK(r.summaries[1].refused());
  bool noted = false;
  for (const auto& n : r.notes) {
    noted |= n.find("pulled: level h = 0.02 off its joints") == 0 &&
             n.find("joint E violated by 0.002 m") != std::string::npos;
  }
  CHECK(noted);
  CHECK(r.refused());  // the pulled method has no order
}

}  // namespace
}  // namespace flexref::studies
