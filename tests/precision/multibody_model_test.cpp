/// \file multibody_model_test.cpp
/// Several bodies, rigid and flexible, and what acts between them in extended/quad
/// (precision/ode_system.hpp):
/// - against core::Model at random states (model_agreement.hpp), coupled and LTE: a free
///   flexible body hinged to the ground by a revolute bushing, a rigid block on a spherical
///   bushing, a second flexible body on a pivot or prescribed, joined to the block; sphere–sphere
///   pairs between two nodes and between a node and the block, a gap support on the block,
///   charges on two bodies, forces at nodes and torques. Each pair must push in some states and
///   not in all, or the check would not see its force;
/// - rigid scenes through the same model, a gap support on a rigid body among them, against
///   core::Model;
/// - the bundled hinged_spinner_strike (the rotor striking the block): quad's energy balance
///   closes (its three precisions in order: flexible_model_test, kFlexibleScenes).
#include <algorithm>
#include <boost/multiprecision/float128.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "contact/bushing.hpp"
#include "contact/contact.hpp"
#include "core/output_times.hpp"
#include "precision/high_precision_reference.hpp"
#include "tests/precision/model_agreement.hpp"
#include "tests/precision/precision_order.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

/// The tip node of flexible_spinner's beam (ten elements of four nodes each: node 40 at
/// x = 1.1 m, flexible/beam_model.cpp).
constexpr int kTipNode = 40;
/// The scenes' plane of motion, z = 3 m: random states (±1 m) keep the charges above the
/// potential's wall at z = 0.
constexpr double kHeight = 3.0;

/// The bundled scenes/hinged_spinner_strike.toml: a flexible rotor (body 0, hub and beam,
/// spinning at 5 rad/s about z) hinged to the ground at its hub by a damped revolute bushing, and
/// a rigid block (body 1) on a damped spherical bushing, whose 10 cm sphere the tip's (5 cm, at
/// the deforming tip node) strikes after about a quarter turn: contact "strike", linear law with
/// damping and friction.
scene::SceneSpec hinged_spinner_and_block() {
  scene::SceneSpec spec = spec_of("scenes/hinged_spinner_strike.toml");
  // Tolerance: the root's 0.1 plus the 1 m length: one rounding (≤ 1.1e-16 relative).
  REQUIRE(spec.bodies.front().description.flexible->modal.p_BoNode_B(0, kTipNode) ==
          Approx(1.1).epsilon(1e-15));
  REQUIRE(spec.contacts.front().pairs.front().node_b.node == kTipNode);
  return spec;
}

/// The same lifted to z = kHeight (bodies and the joints' ground points).
scene::SceneSpec lifted(scene::SceneSpec spec) {
  for (scene::BodySpec& b : spec.bodies) b.description.initial.p_WBo.z() += kHeight;
  for (scene::JointSpec& j : spec.joints) {
    if (j.b.body == contact::kGround) j.b.point.z() += kHeight;
  }
  return spec;
}

/// hinged_spinner_and_block, lifted, with a second copy of its rotor (body 2) on a pivot at its
/// hub, at (2.3, 0, 0) turned 180° about z (its tip toward the first one's), or prescribed (spun up
/// about z to 3 rad/s over 0.5 s); joined to the block by a damped revolute bushing; large spheres
/// (40 cm) at the two tips (pair "tips", node against node), a planar gap support "stop" at a point
/// of the block, two charges (on the block and on body 2's hub), a harmonic force at body 2's node
/// 20 (its work W_a tracked) and a body-frame torque on the block. For random states: the spheres
/// are large so that some states put them through each other (the strike's grown to 50 cm on the
/// block and 30 cm at the tip).
scene::SceneSpec three_bodies(bool prescribed) {
  scene::SceneSpec spec = lifted(hinged_spinner_and_block());
  scene::BodySpec second = spec.bodies.front();
  core::RigidBodyDescription& d = second.description;
  d.name = "spinner2";
  d.points.clear();
  d.initial.p_WBo = Eigen::Vector3d(2.3, 0.0, kHeight);
  d.initial.theta_WB = Eigen::Vector4d(0.0, 0.0, 0.0, 1.0);
  d.initial.v_WBo.setZero();
  if (prescribed) {
    d.motion = core::MotionKind::kPrescribed;
    d.prescribed.axis_W = Eigen::Vector3d::UnitZ();
    // Spinning up at t = 0.3: α̅ ≠ 0, so the drive torque's J α̅ part and the known rows count.
    d.prescribed.law.kind = core::AngleLaw::Kind::kSpinUp;
    d.prescribed.law.rate = 3.0;
    d.prescribed.law.spin_up_time = 0.5;
  } else {
    d.motion = core::MotionKind::kPivot;
    d.p_BoPivot_B = Eigen::Vector3d::Zero();
  }
  const Eigen::Matrix3Xd nodes = d.flexible->modal.p_BoNode_B;
  spec.bodies.push_back(second);

  scene::JointSpec link;  // a revolute bushing between two bodies: τ on one, −τ on the other
  link.revolute = true;
  link.a = {2, Eigen::Vector3d(0.0, 0.1, 0.0), Eigen::Vector3d::UnitZ()};
  link.b = {1, Eigen::Vector3d(0.0, 0.0, 0.05), Eigen::Vector3d(0.0, 1.0, 1.0)};
  link.parameters = {2e4, 5.0, 50.0, 0.5};
  spec.joints.push_back(link);

  spec.contacts.front().pairs.front().radius_a = 0.5;  // the block's sphere
  spec.contacts.front().pairs.front().radius_b = 0.3;  // the first tip's
  scene::ContactSpec tips = spec.contacts.front();
  tips.name = "tips";
  contact::ContactPair pair =
      contact::ContactPair::sphere_sphere(2, nodes.col(kTipNode), 0.4, 0, nodes.col(kTipNode), 0.4);
  pair.node_a.node = kTipNode;
  pair.node_b.node = kTipNode;
  tips.pairs = {pair};
  spec.contacts.push_back(tips);

  scene::ContactSpec stop = spec.contacts.front();
  stop.name = "stop";
  stop.pairs.clear();
  scene::GapSupportSpec gap;
  gap.body = 1;
  gap.p_BoN_B = Eigen::Vector3d(0.1, 0.0, 0.0);
  gap.geometry.kind = contact::GapSupportGeometry::Kind::kPlanar;
  gap.geometry.p_WS = spec.bodies[1].description.initial.p_WBo;
  gap.geometry.a_W = Eigen::Vector3d(1.0, 0.0, 0.0);
  gap.geometry.m_W = Eigen::Vector3d(0.0, 0.3, 1.0).normalized();
  gap.geometry.clearance = 0.6;
  stop.gap = gap;
  spec.contacts.push_back(stop);

  scene::PotentialSpec field;
  field.alpha = 0.5;
  field.beta = 0.01;
  field.p_WM = Eigen::Vector3d(1.0, 0.5, kHeight + 2.0);
  field.charges = {{1, Eigen::Vector3d(0.05, 0.0, 0.0), 1.5},
                   {2, Eigen::Vector3d(0.0, 0.1, 0.0), 2.0}};
  spec.potentials.push_back(field);

  scene::LoadSpec harmonic;
  harmonic.body = 2;
  harmonic.node = 20;
  harmonic.p_BoP_B = nodes.col(20);
  harmonic.value = Eigen::Vector3d(0.0, 0.4, 0.3);
  harmonic.profile = core::TimeProfile::harmonic(2.0, 0.3);
  spec.loads.push_back(harmonic);
  scene::LoadSpec torque;
  torque.torque = true;
  torque.body = 1;
  torque.frame = core::LoadFrame::kBody;
  torque.value = Eigen::Vector3d(0.1, -0.2, 0.3);
  spec.loads.push_back(torque);
  return spec;
}

TEST_CASE("bodies, joints and contacts between them agree with core::Model at random states",
          "[precision]") {
  // The random states (each free Br within ±1 m, any attitude, q_f ~ 0.05 moving a tip by
  // ~20 cm) put the 40 cm tip spheres through each other in some states, the tip through the
  // block's sphere (80 cm in all) in some, and the
  // block's point outside the ±0.6 m gap in some.
  std::map<std::string, int> by_channel;
  int checked = 0;
  unsigned seed = 500;
  for (const auto formulation :
       {core::FlexibleFormulation::kCoupled, core::FlexibleFormulation::kLte}) {
    CAPTURE(core::to_string(formulation));
    for (const bool prescribed : {false, true}) {
      CAPTURE(prescribed);
      for (int k = 0; k < 6; ++k) {
        check_against_core_model(three_bodies(prescribed), formulation, 0.3, {.q = 0.05}, ++seed,
                                 &by_channel);
        checked += 4;
      }
    }
    check_against_core_model(lifted(hinged_spinner_and_block()), formulation, 0.3, {.q = 0.05},
                             ++seed, &by_channel);
  }
  INFO(by_channel["tips.fn"] << ", " << by_channel["strike.fn"] << " and " << by_channel["stop.fn"]
                             << " of " << checked << " random states with the tips, the strike "
                             << "and the stop in contact");
  for (const char* channel : {"tips.fn", "strike.fn", "stop.fn"}) {
    CAPTURE(channel);
    CHECK(by_channel[channel] > 0);
    CHECK(by_channel[channel] < checked);
  }
}

TEST_CASE("rigid scenes through the multibody model agree with core::Model", "[precision]") {
  // A rigid body is a body without modes: its invariants (mass, m c, second moment about Br)
  // come from the hub part alone, and a free or pivot body's rows are solved as Newton–Euler's
  // (a prescribed one's through the 6 × 6 blocks: generic_force_elements_test's driven
  // pendulum). Large moves (±1 m, any attitude) here; the gap support on a rigid body is
  // something only this model's rigid bodies carry besides core::Model.
  scene::SceneSpec gap = spec_of("scenes/double_pendulum_impacts.toml");
  scene::ContactSpec stop;
  stop.name = "stop";
  stop.law.linear = true;
  stop.law.stiffness = 1e4;
  stop.law.damping = 5.0;
  stop.friction.mu = 0.3;
  stop.friction.v_reg = 0.01;
  scene::GapSupportSpec support;
  support.body = 1;
  support.p_BoN_B = Eigen::Vector3d(0.3, 0.0, 0.0);
  support.geometry.kind = contact::GapSupportGeometry::Kind::kCircular;
  // About rod2's initial origin: the random states (±1 m) leave the point inside the 0.8 m
  // clearance in some and outside in others.
  support.geometry.p_WS = gap.bodies[1].description.initial.p_WBo;
  support.geometry.a_W = Eigen::Vector3d(0.0, 0.0, 1.0);
  support.geometry.clearance = 0.8;
  stop.gap = support;
  gap.contacts.push_back(stop);
  unsigned seed = 700;
  for (const char* file :
       {"scenes/book_toss.toml", "scenes/heavy_top.toml", "scenes/tippe_top.toml",
        "scenes/coulomb_wall.toml", "scenes/double_pendulum_impacts.toml",
        "scenes/pendulum_on_sliding_support.toml", "scenes/sliding_block.toml"}) {
    CAPTURE(file);
    check_against_core_model(spec_of(file), core::FlexibleFormulation::kCoupled, 0.2, {}, ++seed);
  }
  std::map<std::string, int> by_channel;
  for (int k = 0; k < 4; ++k) {
    check_against_core_model(gap, core::FlexibleFormulation::kCoupled, 0.2, {}, ++seed,
                             &by_channel);
  }
  INFO(by_channel["stop.fn"] << " of 16 states with the stop in contact");
  CHECK(by_channel["stop.fn"] > 0);
  CHECK(by_channel["stop.fn"] < 16);
}

TEST_CASE("a flexible body striking a rigid block on bushings: quad's energy balance",
          "[precision]") {
  // Over 0.5 s the tip sphere strikes the block (first contact at 0.29 s), with friction, the
  // bushings' and the modes' damping. Quad at rtol 1e-28 closes E − E0 + W_d to its own
  // accuracy: E ~ 18 J (the spin), ~1e-33 J of rounding per step over ~2e3 steps and the located
  // events' ~1e-28 relative; bound 1e-24 J.
  scene::SceneSpec spec = hinged_spinner_and_block();
  spec.end_time = 0.5;
  const std::vector<double> times = core::output_times(spec.end_time, 0.05);
  const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  const std::vector<std::string>& last = run.text.back();
  const auto at_end = [&](const std::string& name) { return std::stod(last[column(run, name)]); };
  const std::size_t balance = column(run, "energy_balance");
  INFO("impacts " << at_end("strike.impacts") << ", wear work " << at_end("strike.wear_work")
                  << " J, dissipated " << at_end("dissipated_work") << " J, energy "
                  << at_end("energy") << " J, balance " << last[balance] << " J, events "
                  << run.events.size());
  CHECK(at_end("strike.impacts") >= 1.0);
  CHECK(at_end("strike.wear_work") > 0.0);
  Quad worst(0);
  for (const std::vector<std::string>& row : run.text) {
    worst = std::max(worst, Quad(abs(Quad(row[balance]))));
  }
  CHECK(static_cast<double>(worst) < 1e-24);
  // Double, extended and quad in that order: flexible_model_test (kFlexibleScenes).
}

}  // namespace
}  // namespace flexref::precision
