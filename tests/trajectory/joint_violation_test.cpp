/// A run's ideal joints measured from its positions (trajectory/joint_violation.hpp): the same
/// Φ as the model's own `J.phi` outputs, a joint pulled apart by 0.1 m found at 0.1 m with its
/// name, a tilted hinge found at the sine of its tilt, a missing body's columns named, and the
/// off-joints verdict on both sides of its threshold.
#include "trajectory/joint_violation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {
namespace {

using Catch::Matchers::Contains;

/// double_pendulum_ideal (rod1 on joint O to the ground, rod2 on joint E to rod1's tip, hinges
/// about z) over 0.2 s, CVODE at rtol 1e-12, tabulated as flexref writes it.
struct PendulumRun {
  scene::Scene scene = scene::read_scene("scenes/double_pendulum_ideal.toml");
  TrajectoryTable table;
  PendulumRun() {
    reference::SolverOptions options;
    options.rtol = 1e-12;
    const std::vector<double> times = core::output_times(0.2, 0.02);
    table = tabulate(*scene.model,
                     reference::solve_reference("cvode", *scene.model, times, options).trajectory);
  }
  const core::Model& model() const { return *scene.model; }
};

/// The table without the joints' own columns (J.fx … J.phi_dot): nothing of the run's own
/// account of its joints is read.
TrajectoryTable without_joint_columns(const TrajectoryTable& t) {
  TrajectoryTable out;
  std::vector<std::size_t> keep;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    const std::string& name = t.columns[c];
    if (name.rfind("O.", 0) == 0 || name.rfind("E.", 0) == 0) continue;
    keep.push_back(c);
    out.columns.push_back(name);
  }
  for (const auto& row : t.rows) {
    std::vector<double> r;
    for (std::size_t c : keep) r.push_back(row[c]);
    out.rows.push_back(std::move(r));
  }
  return out;
}

/// Adds dx to every x column of body `body` (its origin and tracked points).
void shift_x(TrajectoryTable& t, const std::string& body, double dx) {
  for (const std::string& name : {body + ".x", body + ".tip.x"}) {
    const int c = t.column(name);
    REQUIRE(c >= 0);
    for (auto& row : t.rows) row[static_cast<std::size_t>(c)] += dx;
  }
}

/// Turns every body of the table rigidly by `angle` about the world axis `axis` through the
/// origin: positions, points and attitudes (a run that follows the mechanism with an error but
/// keeps its joints).
void turn_all(TrajectoryTable& t, const std::vector<std::string>& bodies, double angle,
              const Eigen::Vector3d& axis) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis));
  for (auto& row : t.rows) {
    for (const std::string& b : bodies) {
      for (const std::string& p : {b, b + ".tip"}) {
        const auto c = static_cast<std::size_t>(t.column(p + ".x"));
        const Eigen::Vector3d r = q * Eigen::Vector3d(row[c], row[c + 1], row[c + 2]);
        row[c] = r.x();
        row[c + 1] = r.y();
        row[c + 2] = r.z();
      }
      const auto e = static_cast<std::size_t>(t.column(b + ".e0"));
      const Eigen::Quaterniond a =
          q * Eigen::Quaterniond(row[e], row[e + 1], row[e + 2], row[e + 3]);
      row[e] = a.w();
      row[e + 1] = a.x();
      row[e + 2] = a.y();
      row[e + 3] = a.z();
    }
  }
}

const JointViolation& joint_named(const std::vector<JointViolation>& joints,
                                  const std::string& name) {
  const auto it = std::find_if(joints.begin(), joints.end(),
                               [&](const JointViolation& j) { return j.name == name; });
  REQUIRE(it != joints.end());
  return *it;
}

ComparisonReport compare_tables(const TrajectoryTable& run, const TrajectoryTable& reference) {
  RunData data;
  data.source = "run";
  data.table = run;
  for (std::size_t r = 0; r < run.rows.size(); ++r) data.lines.push_back(static_cast<int>(r + 2));
  return compare_run(data, reference);
}

TEST_CASE("a run's joints from its positions equal the model's own J.phi", "[joint_violation]") {
  const PendulumRun run;
  const std::vector<JointViolation> joints = measure_joints(run.model(), run.table);
  REQUIRE(joints.size() == 2);
  for (const JointViolation& j : joints) {
    const int phi = run.table.column(j.name + ".phi");
    REQUIRE(phi >= 0);
    double largest = 0.0;
    for (const auto& row : run.table.rows) {
      largest = std::max(largest, row[static_cast<std::size_t>(phi)]);
    }
    INFO(j.name << ": from positions " << j.value() << ", J.phi " << largest);
    CHECK(j.measured);
    // J.phi comes from the state (p_WBr, θ), this from p_WBo and θ written with 17 digits:
    // the two differ by the rounding of |p| ≤ 2 m, 2 × 2.2e-16 × 2 ≈ 1e-15.
    CHECK(std::abs(j.value() - largest) <= 1e-15);
    // CVODE at rtol 1e-12 keeps the joints within 1e-9 m (docs/joints.md, at rtol 1e-10).
    CHECK(j.value() <= 1e-9);
  }
}

TEST_CASE("a joint pulled apart is seen by name and size, a tilted hinge by its sine",
          "[joint_violation]") {
  const PendulumRun run;
  TrajectoryTable pulled = without_joint_columns(run.table);
  shift_x(pulled, "rod2", 0.1);
  const std::vector<JointViolation> joints = measure_joints(run.model(), pulled);
  // E joins rod2's origin to rod1's tip: Φ_x = 0.1 plus the reference's own ≤ 1e-9.
  CHECK(std::abs(joint_named(joints, "E").length - 0.1) <= 1e-9);
  CHECK(joint_named(joints, "E").angle <= 1e-9);
  CHECK(joint_named(joints, "O").value() <= 1e-9);  // rod1 did not move

  // rod2 turned by δ about its own x axis (along the rod): its hinge axis tilts out of the plane
  // by δ and the rows Z_b·X_a, Z_b·Y_a reach sin δ.
  const double delta = 1e-3;
  TrajectoryTable tilted = without_joint_columns(run.table);
  const auto e = static_cast<std::size_t>(tilted.column("rod2.e0"));
  for (auto& row : tilted.rows) {
    const Eigen::Quaterniond a(row[e], row[e + 1], row[e + 2], row[e + 3]);
    const Eigen::Quaterniond b =
        a * Eigen::Quaterniond(Eigen::AngleAxisd(delta, Eigen::Vector3d::UnitX()));
    row[e] = b.w();
    row[e + 1] = b.x();
    row[e + 2] = b.y();
    row[e + 3] = b.z();
  }
  const std::vector<JointViolation> tilted_joints = measure_joints(run.model(), tilted);
  const JointViolation& E = joint_named(tilted_joints, "E");
  CHECK(std::abs(E.angle - std::sin(delta)) <= 1e-9);
  CHECK(E.length <= 1e-9);  // the turn is about the joint point's own line: no separation
}

TEST_CASE("a body's missing pose columns leave its joints unmeasured and the run off them",
          "[joint_violation]") {
  const PendulumRun run;
  TrajectoryTable table = without_joint_columns(run.table);
  // Only rod1 and the time: rod2's columns gone.
  TrajectoryTable partial;
  std::vector<std::size_t> keep;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    if (table.columns[c].rfind("rod2.", 0) == 0) continue;
    keep.push_back(c);
    partial.columns.push_back(table.columns[c]);
  }
  for (const auto& row : table.rows) {
    std::vector<double> r;
    for (std::size_t c : keep) r.push_back(row[c]);
    partial.rows.push_back(std::move(r));
  }
  const std::vector<JointViolation> joints = measure_joints(run.model(), partial);
  CHECK(joint_named(joints, "O").measured);
  CHECK_FALSE(joint_named(joints, "E").measured);
  CHECK_THAT(joint_named(joints, "E").missing, Contains("rod2.x..rod2.z") && Contains("rod2.e0"));
  const JointVerdict verdict =
      judge_joints(run.model(), joints, measure_joints(run.model(), run.table),
                   compare_tables(partial, run.table));
  CHECK(verdict.off);
  CHECK_THAT(verdict.why, Contains("joint E cannot be measured"));
}

TEST_CASE("the off-joints verdict: a violation small against the error at the joint is on",
          "[joint_violation]") {
  const PendulumRun run;
  const core::Model& model = run.model();
  const std::vector<JointViolation> reference = measure_joints(model, run.table);
  const std::vector<std::string> bodies{"rod1", "rod2"};

  // The intact run against itself, and the whole mechanism turned by ε about the pivot's axis z:
  // an error of ε rad and up to 2ε m, the joints intact.
  CHECK_FALSE(judge_joints(model, reference, reference, compare_tables(run.table, run.table)).off);
  const double eps = 1e-3;
  TrajectoryTable turned = without_joint_columns(run.table);
  turn_all(turned, bodies, eps, Eigen::Vector3d::UnitZ());
  const ComparisonReport turned_report = compare_tables(turned, run.table);
  CHECK_FALSE(judge_joints(model, measure_joints(model, turned), reference, turned_report).off);

  // On top of that turn, rod2 pulled along x by δ. Joint E's error scale is Σ e_p + ρ e_r over
  // rod1 and rod2 (ρ = 1 m: the tips): ε for rod1 (its origin on the axis), about 2ε + δ for
  // rod2 (its origin 1 m from the axis): 3e-3 m + δ. δ = 1e-5 is 0.3 % of it: on; δ = 1e-3 is
  // 25 % (1e-3 / 4e-3), above the 6.7 % of kJointViolationFraction: off, naming E.
  for (const double delta : {1e-5, 1e-3}) {
    TrajectoryTable pulled = turned;
    shift_x(pulled, "rod2", delta);
    const JointVerdict verdict = judge_joints(model, measure_joints(model, pulled), reference,
                                              compare_tables(pulled, run.table));
    INFO("delta = " << delta << ": " << verdict.why);
    CHECK(verdict.off == (delta > 1e-4));
    if (verdict.off) CHECK_THAT(verdict.why, Contains("joint E violated by 0.001 m"));
  }

  // The reference's estimated error as noise: a violation within it is not judged.
  TrajectoryTable pulled = turned;
  shift_x(pulled, "rod2", 1e-3);
  CHECK_FALSE(judge_joints(model, measure_joints(model, pulled), reference,
                           compare_tables(pulled, run.table), 2e-3)
                  .off);
}

TEST_CASE("the off-joints fraction is 1 - 2^-0.1", "[joint_violation]") {
  // A floor δ that is this fraction of a level's error biases the order from it by
  // -log2(1 - δ/e) = 0.1 exactly.
  // The fraction is computed in double: its bias is 0.1 to a few ulps.
  CHECK(std::abs(-std::log2(1.0 - kJointViolationFraction) - 0.1) <= 1e-14);
}

}  // namespace
}  // namespace flexref::trajectory
