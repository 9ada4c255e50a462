#include "trajectory/trajectory_table.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <stdexcept>

#include "core/error.hpp"
#include "core/gravity.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/temp_dir.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::trajectory {
namespace {

core::Model pendulum_like_model() {
  core::RigidBodyDescription d;
  d.name = "rod";
  d.mass = 2.0;
  d.p_BoBcm_B = Eigen::Vector3d(0.5, 0.0, 0.0);
  d.I_Bcm_B = Eigen::Vector3d(0.01, 0.2, 0.2).asDiagonal();
  d.initial.w_WB_B = Eigen::Vector3d(0.1, 0.2, 0.3);
  d.initial.v_WBo = Eigen::Vector3d(1.0, 0.0, 0.0);
  d.points.push_back({"tip", Eigen::Vector3d(1.0, 0.0, 0.0)});
  std::vector<core::Body> bodies{core::Body(d)};
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0, 0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, 2.0, d.p_BoBcm_B}}));
  return core::Model(std::move(bodies), std::move(elements));
}

/// `name` in this program's folder for the tables (removed at exit).
std::string table_temp_path(const std::string& name) {
  static const testing::TempDir dir("trajectory-table");
  return (dir / name).string();
}

TEST_CASE("tabulate names the documented columns and recovers the frame origin", "[trajectory]") {
  const core::Model model = pendulum_like_model();
  core::Trajectory trajectory;
  trajectory.times = {0.0};
  trajectory.states = {model.initial_state()};
  const TrajectoryTable table = tabulate(model, trajectory);
  const std::vector<std::string> expected{"t",         "rod.x",     "rod.y",  "rod.z",  "rod.e0",
                                          "rod.e1",    "rod.e2",    "rod.e3", "rod.vx", "rod.vy",
                                          "rod.vz",    "rod.W1",    "rod.W2", "rod.W3", "rod.tip.x",
                                          "rod.tip.y", "rod.tip.z", "energy"};
  CHECK(table.columns == expected);
  const auto& row = table.rows[0];
  // The origin starts at 0 and moves at (1,0,0): internal Br = Bcm must map back exactly
  // (the map is p − A·c with A = I: exact in floating point).
  CHECK(row[1] == 0.0);
  CHECK(row[8] == 1.0);
  CHECK(row[14] == 1.0);  // tip at (1, 0, 0)
  // energy = ½ m |v_cm|² + ½ ωᵀ I ω + potential (z_cm = 0 → 0); v_cm = v_o + ω × c.
  const Eigen::Vector3d w(0.1, 0.2, 0.3);
  const Eigen::Vector3d v_cm = Eigen::Vector3d(1, 0, 0) + w.cross(Eigen::Vector3d(0.5, 0, 0));
  const double energy =
      0.5 * 2.0 * v_cm.squaredNorm() + 0.5 * w.dot(Eigen::Vector3d(0.01, 0.2, 0.2).cwiseProduct(w));
  CHECK(row.back() == Approx(energy).epsilon(1e-14));
}

TEST_CASE("CSV round trip is exact and comparison of a file with itself is zero", "[trajectory]") {
  const core::Model model = pendulum_like_model();
  core::Trajectory trajectory;
  for (int k = 0; k < 5; ++k) {
    trajectory.times.push_back(0.1 * k);
    core::State s = model.initial_state();
    s[0].theta_WB = rotation::exp_quaternion(Eigen::Vector3d(0.3 * k, -0.1, 0.7 * k));
    trajectory.states.push_back(s);
  }
  const TrajectoryTable table = tabulate(model, trajectory);
  const std::string path = table_temp_path("roundtrip.csv");
  write_csv(table, path);
  const TrajectoryTable back = read_csv(path);
  CHECK(back.columns == table.columns);
  REQUIRE(back.rows.size() == table.rows.size());
  for (std::size_t k = 0; k < table.rows.size(); ++k) CHECK(back.rows[k] == table.rows[k]);
  const ComparisonReport self = compare_trajectories(back, table);
  CHECK(metric_value(self, kDefaultMetric) == 0.0);

  // A rotation of 1e-3 rad about z at every time shows as a geodesic error of 1e-3.
  TrajectoryTable rotated = table;
  for (auto& row : rotated.rows) {
    const rotation::EulerParameters q(row[4], row[5], row[6], row[7]);
    const rotation::EulerParameters r =
        rotation::quaternion_multiply(q, rotation::exp_quaternion(Eigen::Vector3d(0, 0, 1e-3)));
    for (int i = 0; i < 4; ++i) row[static_cast<std::size_t>(4 + i)] = r(i);
  }
  const ComparisonReport report = compare_trajectories(rotated, table);
  CHECK(report.max_rotation_linf == Approx(1e-3).epsilon(1e-9));
  CHECK(metric_value(report, "rotation") == Approx(1e-3).epsilon(1e-9));
  std::filesystem::remove(path);
}

TEST_CASE("read_csv reports file, line and column of bad data", "[trajectory]") {
  const std::string path = table_temp_path("bad.csv");
  {
    std::ofstream out(path);
    out << "t,energy\n0,1\n0.1,x\n";
  }
  try {
    read_csv(path);
    FAIL("expected an InputError");
  } catch (const core::InputError& e) {
    CHECK(e.line() == 3);
    CHECK(e.key() == "energy");
    CHECK(std::string(e.what()).find(path) != std::string::npos);
  }
  std::filesystem::remove(path);
}

TEST_CASE("tabulate refuses a trajectory without one state per output time", "[trajectory]") {
  // A driver that stopped early (an overflowed step count) must not be read past its end.
  const core::Model model = pendulum_like_model();
  core::Trajectory trajectory;
  trajectory.times = {0.0, 0.1, 0.2};
  trajectory.states = {model.initial_state()};
  CHECK_THROWS_AS(tabulate(model, trajectory), std::invalid_argument);
}

TEST_CASE("csv_text keeps a free-text field in one unquoted CSV cell", "[trajectory]") {
  // numpy.genfromtxt splits on every comma, quoted or not: no comma, quote or line break may
  // reach a cell.
  CHECK(csv_text("failed: c2 failed at t = 1, step 3: \"no\"\nconvergence") ==
        "failed: c2 failed at t = 1; step 3: 'no' convergence");
  CHECK(csv_text("ok") == "ok");
}

/// A unit every column that `applies` to must have; `columns` counts them.
struct UnitRule {
  std::string what;
  std::function<bool(const std::string&)> applies;
  std::string unit;
  int columns = 0;
};

/// Checks one unit per column, each rule's unit on the columns it applies to, and that every
/// rule applied to at least one column (a table without such columns fails rather than passing
/// the loop vacuously).
void check_units(const std::vector<std::string>& names, const std::vector<std::string>& units,
                 std::vector<UnitRule> rules) {
  REQUIRE(units.size() == names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    for (UnitRule& rule : rules) {
      if (!rule.applies(names[i])) continue;
      INFO(names[i] << " (" << rule.what << ")");
      CHECK(units[i] == rule.unit);
      ++rule.columns;
    }
  }
  for (const UnitRule& rule : rules) {
    INFO("columns of " << rule.what);
    CHECK(rule.columns > 0);
  }
}

TEST_CASE("trajectory_units gives one unit per column", "[trajectory]") {
  const core::Model model = pendulum_like_model();
  check_units(
      trajectory_columns(model), trajectory_units(model),
      {{"time", [](const std::string& n) { return n == "t"; }, "s"},
       {"Euler parameters",
        [](const std::string& n) { return n.ends_with(".e0") || n.ends_with(".e3"); }, "-"},
       {"velocities", [](const std::string& n) { return n.ends_with(".vx"); }, "m/s"},
       {"angular velocities", [](const std::string& n) { return n.ends_with(".W2"); }, "rad/s"},
       {"positions", [](const std::string& n) { return n.ends_with(".tip.z") || n == "rod.x"; },
        "m"},
       {"energy", [](const std::string& n) { return n == "energy"; }, "J"}});
}

TEST_CASE("trajectory_units covers work and wear columns", "[trajectory]") {
  // tube_support_impact: a dissipating model with applied work and a named contact, whose
  // columns end with energy, dissipated/applied work, balance and four wear outputs.
  const scene::Scene scene = scene::read_scene("scenes/tube_support_impact.toml");
  check_units(
      trajectory_columns(*scene.model), trajectory_units(*scene.model),
      {{"work and balance",
        [](const std::string& n) { return n.ends_with("_work") || n == "energy_balance"; }, "J"},
       {"normal forces", [](const std::string& n) { return n.ends_with(".fn"); }, "N"},
       {"slip speeds", [](const std::string& n) { return n.ends_with(".slip_speed"); }, "m/s"},
       {"impact counts", [](const std::string& n) { return n.ends_with(".impacts"); }, "-"}});
}

}  // namespace
}  // namespace flexref::trajectory
