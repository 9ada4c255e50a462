/// \file generic_force_elements_test.cpp
/// The force elements of the extended/quad model (contacts with friction, bushings, the
/// point-charge potential) against core::Model at random states of the bundled scenes: the
/// accelerations of every body, the rates of the integrals (dissipated power, wear power) and
/// the output row (model_agreement.hpp). The elements are one code (class templates both
/// models run, core/force_element.hpp), so this checks their conversion to S (data, unit
/// vectors, node rows, the element order that numbers the switching functions), the state
/// layout and the outputs.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "contact/contact.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/build_model.hpp"
#include "tests/precision/model_agreement.hpp"
#include "tests/precision/precision_order.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {
namespace {

/// double_pendulum_impacts with its upper rod driven about the y axis through its centre (Bo) by
/// a spin-up law to 3 rad/s over 0.2 s, instead of swinging on its pivot: a prescribed body at a
/// joint's end, under gravity (its centre of mass off the axis would load the drive too).
scene::SceneSpec driven_double_pendulum() {
  scene::SceneSpec spec = spec_of("scenes/double_pendulum_impacts.toml");
  core::RigidBodyDescription& d = spec.bodies.front().description;
  d.motion = core::MotionKind::kPrescribed;
  d.prescribed.axis_W = Eigen::Vector3d::UnitY();
  d.prescribed.law.kind = core::AngleLaw::Kind::kSpinUp;
  d.prescribed.law.rate = 3.0;          // rad/s
  d.prescribed.law.spin_up_time = 0.2;  // s
  return spec;
}

/// The scene with each sphere–plane pair's plane moved to touch its sphere at the initial state,
/// so that the small random moves put the pair in contact in some states and not in others
/// (bouncing_ball's ball starts 1 m up, double_pendulum_impacts' tip 2.8 m from its wall).
scene::SceneSpec touching(scene::SceneSpec spec) {
  for (scene::ContactSpec& c : spec.contacts) {
    for (contact::ContactPair& p : c.pairs) {
      if (p.kind != contact::ContactPair::Kind::kSpherePlane) continue;
      const core::BodyInitialState& init =
          spec.bodies[static_cast<std::size_t>(p.body_b)].description.initial;
      const Eigen::Vector3d p_WC =
          init.p_WBo + rotation::rotation_matrix(init.theta_WB.normalized()) * p.p_BoCb_B;
      p.p_WQ = p_WC - p.radius_b * p.n_W;
    }
  }
  return spec;
}

TEST_CASE("contacts, bushings and potentials of the generic model agree with core::Model",
          "[precision]") {
  // Small moves of position and attitude (joints stretch by ~1e-3 m, contacts penetrate or open
  // by as much) and O(1) velocities: model_agreement.hpp's check, 1e-9 relative to each body's
  // largest acceleration (penalty stiffnesses of 1e6 make the forces differences of ~1e4 N
  // terms: ~1e5 ε). Every contact must push in some of the states, or the check would not see
  // its force.
  unsigned seed = 7;
  for (const char* file :
       {"scenes/pendulum_on_sliding_support.toml", "scenes/double_pendulum_impacts.toml",
        "scenes/coulomb_wall.toml", "scenes/sliding_block.toml", "scenes/top_on_plane.toml",
        "scenes/tippe_top.toml", "scenes/bouncing_ball.toml", "driven"}) {
    CAPTURE(file);
    const std::string name = file;
    scene::SceneSpec spec = touching(name == "driven" ? driven_double_pendulum() : spec_of(file));
    for (std::size_t c = 0; c < spec.contacts.size(); ++c) {
      spec.contacts[c].name = "c" + std::to_string(c);  // wear channels on every contact
    }
    std::map<std::string, int> by_channel;
    for (int k = 0; k < 4; ++k) {
      check_against_core_model(spec, core::FlexibleFormulation::kCoupled, 0.1,
                               {.position = 1e-3, .attitude = 1e-3, .velocity = 1.0, .rate = 1.0},
                               ++seed, &by_channel);
    }
    for (std::size_t c = 0; c < spec.contacts.size(); ++c) {
      // Appended, not "c" + to_string(c): GCC 12 warns falsely (-Wstringop-overflow) on the
      // inlined operator+ of a literal and a temporary.
      std::string channel = "c";
      channel += std::to_string(c);
      channel += ".fn";
      INFO(channel << " pushed in " << by_channel[channel] << " of 16 states");
      CHECK(by_channel[channel] > 0);
    }
  }
}

TEST_CASE("double, extended and quad agree in that order on a scene with joints and impacts",
          "[precision]") {
  // double_pendulum_impacts over 0.1 s (its stiff bushings make quad extrapolation slow: about
  // 30 s of quad per simulated second on one core, docs/precision.md).
  check_precision_order("scenes/double_pendulum_impacts.toml", 0.1);
}

TEST_CASE("double, extended and quad agree in that order on the sustained-contact scenes",
          "[precision][long_quad]") {
  // The scenes whose contacts or joints stay loaded: the tops spin on their plane, the pendulum
  // hangs from a block sliding on its support. Quad resolves the contact's and the joint's stiff
  // modes (13-20 s of quad per 0.5 s on one core, docs/precision.md), so the unit label covers
  // 0.1 s and the study label 1 s (precision_order_study_test.cpp).
  for (const char* file : kSustainedContactScenes) check_precision_order(file, 0.1);
}

TEST_CASE("double, extended and quad agree in that order with a prescribed rigid body",
          "[precision][long_quad]") {
  // The driven double pendulum over 0.3 s: the spin-up (φ⁗ jumps at 0.2 s, a stop of the
  // integrators) and after; the drive torque is among the compared columns' sources.
  check_precision_order(driven_double_pendulum(), 0.3);
  // The drive torque, from the joint's stiff force (k = 1e6 N/m): extended (rtol 1e-16) and
  // quad agree to what extended's state errors (~1e-15 relative) give through the joint, some
  // 1e-15 m × 1e6 N/m × 0.5 m ≈ 1e-9 N·m on torques of ~10 N·m; the bound 1e-8 relative.
  scene::SceneSpec spec = driven_double_pendulum();
  spec.end_time = 0.3;
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun quad = solve_high_precision(spec, times, Precision::kQuad, 1e-26);
  const HighPrecisionRun ext = solve_high_precision(spec, times, Precision::kExtended, 1e-16);
  const auto column = static_cast<std::size_t>(
      std::find(quad.columns.begin(), quad.columns.end(), "rod1.drive_torque") -
      quad.columns.begin());
  REQUIRE(column < quad.columns.size());
  double largest = 0.0, worst = 0.0;
  for (std::size_t r = 0; r < quad.table.rows.size(); ++r) {
    largest = std::max(largest, std::abs(quad.table.rows[r][column]));
    worst = std::max(worst, std::abs(quad.table.rows[r][column] - ext.table.rows[r][column]));
  }
  INFO("largest drive torque " << largest << " N m, extended vs quad " << worst);
  CHECK(largest > 1.0);  // the drive works: the rods' weight and the spin-up load it
  CHECK(worst <= 1e-8 * largest);
}

}  // namespace
}  // namespace flexref::precision
