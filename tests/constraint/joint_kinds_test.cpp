/// \file joint_kinds_test.cpp
/// One scene per ideal-joint kind (tests/support/joint_kind_scenes.hpp: prismatic, driven
/// prismatic, cylindrical, universal, fixed, distance, driven revolute), integrated by every
/// reference solver (CVODE, IDA, ARKODE, Odeint) and by the Lie-group generalized-α scheme,
/// against an oracle that does not use the constrained solve (closed forms, the exact
/// torque-free motion of the merged body, the point-mass pendulum's own equation): the bodies'
/// centres of mass, attitudes and velocities at every output, the joints' violations, and the
/// reactions as the output table writes them (`J.fx … J.tz`).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "lie/genalpha.hpp"
#include "lie/run_scheme.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/so3.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/joint_kind_scenes.hpp"
#include "tests/support/solver_options.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::constraint {
namespace {

/// The largest differences from the oracle over the outputs: each relative to the scene's
/// scale of its kind (testing::JointKindScene), and the largest joint violation |Φ| (m or rad).
struct KindErrors {
  double position = 0.0, attitude = 0.0, velocity = 0.0, angular_velocity = 0.0;
  double force = 0.0, torque = 0.0, violation = 0.0;
  std::string describe() const {
    std::ostringstream o;
    o << "relative errors: position " << position << ", attitude " << attitude << " rad"
      << ", velocity " << velocity << ", angular velocity " << angular_velocity << ", force "
      << force << ", torque " << torque << "; violation " << violation;
    return o.str();
  }
};

KindErrors kind_errors(const testing::JointKindScene& scene, const core::Trajectory& trajectory,
                       const trajectory::TrajectoryTable& table) {
  const std::vector<testing::OracleSample> oracle = scene.oracle_at(trajectory.times);
  REQUIRE(oracle.size() == trajectory.times.size());
  KindErrors e;
  for (std::size_t k = 0; k < oracle.size(); ++k) {
    const core::State& state = trajectory.states[k];
    REQUIRE(oracle[k].bodies.size() == state.size());
    for (std::size_t b = 0; b < state.size(); ++b) {
      const testing::OracleBody& o = oracle[k].bodies[b];
      const core::BodyState& s = state[b];
      const Eigen::Matrix3d R = rotation::rotation_matrix(s.theta_WB);
      // Free rigid bodies: Br is the centre of mass.
      e.position = std::max(e.position, (s.p_WBr - o.p_WC).norm() / scene.length);
      e.attitude = std::max(e.attitude, rotation::log_so3(o.R_WB.transpose() * R).norm());
      e.velocity = std::max(e.velocity, (s.v_WBr - o.v_WC).norm() / scene.speed);
      e.angular_velocity = std::max(e.angular_velocity, (R * s.w_WB_B - o.w_W).norm() / scene.rate);
    }
    for (const auto& [name, value] : oracle[k].columns) {
      const int c = table.column(name);
      REQUIRE(c >= 0);
      const double d = std::abs(table.rows[k][static_cast<std::size_t>(c)] - value);
      const bool force = name.substr(name.size() - 3, 2) == ".f";
      double& worst = force ? e.force : e.torque;
      worst = std::max(worst, d / (force ? scene.force : scene.torque));
    }
    for (std::size_t c = 0; c < table.columns.size(); ++c) {
      const std::string& name = table.columns[c];
      if (name.size() > 4 && name.substr(name.size() - 4) == ".phi") {
        e.violation = std::max(e.violation, std::abs(table.rows[k][c]));
      }
    }
  }
  return e;
}

/// Every reference solver on the scene at rtol 1e-10 against its oracle.
void check_joint_kind_references(const testing::JointKindScene& kind) {
  const double rtol = 1e-10;
  const scene::Scene scene = scene::parse_scene(kind.toml, kind.kind + ".toml");
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);
  for (const std::string solver : {"cvode", "ida", "arkode", "odeint"}) {
    INFO(kind.kind << " (" << kind.oracle << "), " << solver);
    reference::ReferenceRun run;
    try {
      run = reference::solve_reference(solver, *scene.model, times, testing::with_rtol(rtol));
    } catch (const core::SolverError& error) {
      FAIL_CHECK(error.what());
      continue;
    }
    const trajectory::TrajectoryTable table = trajectory::tabulate(*scene.model, run.trajectory);
    const KindErrors e = kind_errors(kind, run.trajectory, table);
    INFO(e.describe() << " (" << run.stats.steps << " steps)");
    // The states err by the solver's global error: local errors ≤ rtol × |y| per step (atol =
    // rtol, |y| ≲ 10 in the scenes' units) carried over ≤ 1e3 steps by motions that are not
    // chaotic (uniform, periodic or kinematic): ≤ 1e3 × rtol × 10 = 1e4 rtol of each scale.
    // Measured: Odeint's six steps through the driven prismatic's spin-up 1.1e-8 in position
    // and 6.7e-8 in velocity, everything else ≤ 1e-8 (IDA on the welded pair: 8.5e-9 in
    // attitude). A wrong row, sign or drive moves them by O(1) of their scale.
    const double bound = 1e4 * rtol;
    CHECK(e.position <= bound);
    CHECK(e.attitude <= bound);
    CHECK(e.velocity <= bound);
    CHECK(e.angular_velocity <= bound);
    // The reactions are the accelerations' image through the masses at the state: the state's
    // relative error carried through (measured ≤ 6e-9).
    CHECK(e.force <= bound);
    CHECK(e.torque <= bound);
    // Φ: a position error, at most the positions' (a driven mechanism's motion is all
    // violation: Odeint's 3.3e-8 m above); CVODE's Baumgarte drift and the explicit solvers'
    // stay at the local errors' size, IDA's GGL form at round-off.
    CHECK(e.violation <= bound * kind.length);
  }
}

/// The Lie-group generalized-α scheme (ρ∞ = 0.9, h = 1e-3) on the scene against its oracle.
void check_joint_kind_genalpha(const testing::JointKindScene& kind) {
  const scene::Scene scene = scene::parse_scene(kind.toml, kind.kind + ".toml");
  const std::vector<double> times = core::output_times(scene.end_time, scene.output_step);
  const double h = 1e-3;
  INFO(kind.kind << " (" << kind.oracle << "), genalpha h = " << h);
  lie::GenAlphaStepper stepper(*scene.model, lie::GenAlphaParameters::from_rho_inf(0.9));
  core::Trajectory trajectory;
  try {
    trajectory = lie::run_scheme(*scene.model, stepper, h, times);
  } catch (const core::SolverError& error) {
    FAIL_CHECK(error.what());
    return;
  }
  const trajectory::TrajectoryTable table = trajectory::tabulate(*scene.model, trajectory);
  const KindErrors e = kind_errors(kind, trajectory, table);
  INFO(e.describe());
  // Second order: the global error of each quantity is C (h ω)² of its scale, ω the motion's
  // fastest rate (JointKindScene::rate), with C of order the error constant per radian of
  // motion times the ≲ 10 rad covered: measured C ≤ 0.22 (the spherical pendulum's position
  // and velocity; the others ≤ 0.17, motions of uniform acceleration or rotation exact to
  // round-off). C = 1 keeps a margin of 4.5; a wrong row, sign or drive is an O(1) error.
  const double bound = std::pow(h * kind.rate, 2);
  CHECK(e.position <= bound);
  CHECK(e.attitude <= bound);
  CHECK(e.velocity <= bound);
  CHECK(e.angular_velocity <= bound);
  CHECK(e.force <= bound);
  CHECK(e.torque <= bound);
  // Index 3: Φ(q_{n+1}) = 0 is a Newton equation solved to 1e-14 of the positions (≤ 3 m).
  CHECK(e.violation <= 1e-13);
}

TEST_CASE("joint kinds: prismatic, free fall along an inclined guide, by every reference",
          "[constraint][joint_kinds]") {
  check_joint_kind_references(testing::prismatic_guide_scene(false));
}

TEST_CASE("joint kinds: prismatic, free fall along an inclined guide, by genalpha",
          "[constraint][joint_kinds][genalpha]") {
  check_joint_kind_genalpha(testing::prismatic_guide_scene(false));
}

TEST_CASE("joint kinds: driven prismatic, the spin-up law along a guide, by every reference",
          "[constraint][joint_kinds]") {
  check_joint_kind_references(testing::prismatic_guide_scene(true));
}

TEST_CASE("joint kinds: driven prismatic, the spin-up law along a guide, by genalpha",
          "[constraint][joint_kinds][genalpha]") {
  check_joint_kind_genalpha(testing::prismatic_guide_scene(true));
}

TEST_CASE("joint kinds: cylindrical, spinning and sliding on a guide, by every reference",
          "[constraint][joint_kinds]") {
  check_joint_kind_references(testing::cylindrical_spindle_scene());
}

TEST_CASE("joint kinds: cylindrical, spinning and sliding on a guide, by genalpha",
          "[constraint][joint_kinds][genalpha]") {
  check_joint_kind_genalpha(testing::cylindrical_spindle_scene());
}

TEST_CASE("joint kinds: universal, a driven Hooke joint, by every reference",
          "[constraint][joint_kinds]") {
  check_joint_kind_references(testing::hooke_joint_scene());
}

TEST_CASE("joint kinds: universal, a driven Hooke joint, by genalpha",
          "[constraint][joint_kinds][genalpha]") {
  check_joint_kind_genalpha(testing::hooke_joint_scene());
}

TEST_CASE("joint kinds: fixed, a welded pair as the merged body, by every reference",
          "[constraint][joint_kinds]") {
  check_joint_kind_references(testing::welded_pair_scene());
}

TEST_CASE("joint kinds: fixed, a welded pair as the merged body, by genalpha",
          "[constraint][joint_kinds][genalpha]") {
  check_joint_kind_genalpha(testing::welded_pair_scene());
}

TEST_CASE("joint kinds: distance, a spherical pendulum on a massless rod, by every reference",
          "[constraint][joint_kinds]") {
  check_joint_kind_references(testing::spherical_pendulum_scene());
}

TEST_CASE("joint kinds: distance, a spherical pendulum on a massless rod, by genalpha",
          "[constraint][joint_kinds][genalpha]") {
  check_joint_kind_genalpha(testing::spherical_pendulum_scene());
}

TEST_CASE("joint kinds: driven revolute, a hinge under the spin-up law, by every reference",
          "[constraint][joint_kinds]") {
  check_joint_kind_references(testing::driven_hinge_scene());
}

TEST_CASE("joint kinds: driven revolute, a hinge under the spin-up law, by genalpha",
          "[constraint][joint_kinds][genalpha]") {
  check_joint_kind_genalpha(testing::driven_hinge_scene());
}

}  // namespace
}  // namespace flexref::constraint
