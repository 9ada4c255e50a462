/// \file flexible_model_test.cpp
/// The flexible body in extended/quad (precision/ode_system.hpp):
/// - against core::Model at random states, coupled and LTE, free, pivot and prescribed, with
///   geometric stiffening, gravity, modal damping and forces at nodes and hub points: the
///   accelerations, the integrals' rates and the output row. The equations are one code (the
///   force elements, body rows, inertia terms and solves are templates both models run), so this
///   checks what each model writes itself: the invariants' reference point and the bodies' data
///   formed in S, the state layout, the elements' conversion to S and the outputs;
/// - double, extended and quad references in that order on the bundled flexible scenes;
/// - conservation of energy in quad by the free flexible body once its torque pulse is over.
#include <algorithm>
#include <boost/multiprecision/float128.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "contact/contact.hpp"
#include "contact/gap_support.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "precision/ode_system.hpp"
#include "scene/build_model.hpp"
#include "tests/precision/model_agreement.hpp"
#include "tests/precision/precision_order.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

/// flexible_spinner with everything the model carries: gravity, 2 % modal damping, a harmonic
/// force at node 9 (an inner node of the beam's third element, x = 0.32 m; its work W_a is
/// tracked), a body-frame force at a hub point and a world force at a node; free, or on a pivot at
/// the hub rim.
scene::SceneSpec loaded_spinner(bool pivot) {
  scene::SceneSpec spec = spec_of("scenes/flexible_spinner.toml");
  spec.g_W = Eigen::Vector3d(0.3, -0.2, -9.81);
  core::RigidBodyDescription& d = spec.bodies.front().description;
  d.flexible->modal.damping_ratio.setConstant(0.02);
  if (pivot) {
    d.motion = core::MotionKind::kPivot;
    d.p_BoPivot_B = Eigen::Vector3d(0.0, 0.1, 0.02);
    d.initial.v_WBo.setZero();
  }
  scene::LoadSpec harmonic;
  harmonic.body = 0;
  harmonic.node = 9;
  harmonic.p_BoP_B = d.flexible->modal.p_BoNode_B.col(9);
  harmonic.value = Eigen::Vector3d(0.0, 0.4, 0.3);
  harmonic.profile = core::TimeProfile::harmonic(2.0, 0.3);
  spec.loads.push_back(harmonic);
  scene::LoadSpec hub;
  hub.body = 0;
  hub.p_BoP_B = Eigen::Vector3d(0.05, -0.1, 0.02);
  hub.frame = core::LoadFrame::kBody;
  hub.value = Eigen::Vector3d(1.0, 0.5, -2.0);
  spec.loads.push_back(hub);
  scene::LoadSpec node;
  node.body = 0;
  node.node = 5;
  node.p_BoP_B = d.flexible->modal.p_BoNode_B.col(5);
  node.value = Eigen::Vector3d(-0.5, 0.2, 0.7);
  spec.loads.push_back(node);
  return spec;
}

/// flexible_spinner (free) with a planar gap support at node 9 (x = 0.32 m), planes at ±2 mm
/// about the undeformed node along the body's y at t = 0, a linear law with its damping and
/// friction, and a named wear channel: the planar geometry, the linear law and a free body.
scene::SceneSpec spinner_in_planar_support() {
  scene::SceneSpec spec = loaded_spinner(false);
  const core::RigidBodyDescription& d = spec.bodies.front().description;
  scene::ContactSpec c;
  scene::GapSupportSpec gap;
  gap.node = 9;
  gap.p_BoN_B = d.flexible->modal.p_BoNode_B.col(9);
  gap.geometry.kind = contact::GapSupportGeometry::Kind::kPlanar;
  gap.geometry.p_WS = d.initial.p_WBo + gap.p_BoN_B;
  gap.geometry.a_W = Eigen::Vector3d(1.0, 0.0, 0.2);
  gap.geometry.m_W = Eigen::Vector3d(0.1, 1.0, 0.0);
  gap.geometry.clearance = 2e-3;
  c.gap = gap;
  c.name = "stop";
  c.law.linear = true;
  c.law.stiffness = 2e5;
  c.law.damping = 40.0;
  c.friction.mu = 0.2;
  c.friction.v_reg = 0.01;
  spec.contacts.push_back(c);
  return spec;
}

/// flexible_spinner under gravity with its Bo at height h over a ground plane through
/// (0, 0, plane_z) tilted 0.1 rad about y, a sphere (r = 2 cm) at its tip (node 40, "node10":
/// ten elements of four nodes each, flexible/beam_model.cpp) and one
/// (r = 10 cm) at the hub point (0, 0, −0.05) on it, each a named contact (wear channels "tip"
/// and "hub", pairs 0 and 1) with a linear law, damping and friction; and a point-charge potential
/// (attractor 2 m above Bo, wall z = 0) with two hub charges. Everything a flexible body carries in
/// extended/quad besides gap supports. Without the scene's torque pulse, whose work no integral
/// tracks: E − E0 + W_d closes.
scene::SceneSpec spinner_on_plane_in_field(double height, double plane_z) {
  scene::SceneSpec spec = spec_of("scenes/flexible_spinner.toml");
  spec.loads.clear();
  spec.g_W = Eigen::Vector3d(0.0, 0.0, -9.81);
  core::RigidBodyDescription& d = spec.bodies.front().description;
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, height);
  d.flexible->modal.damping_ratio.setConstant(0.01);
  const Eigen::Vector3d p_WQ(0.0, 0.0, plane_z);
  const Eigen::Vector3d n_W(std::sin(0.1), 0.0, std::cos(0.1));
  const int tip_node = 40;
  // Tolerance: the root's 0.1 plus the 1 m length: one rounding (≤ 1.1e-16 relative).
  REQUIRE(d.flexible->modal.p_BoNode_B(0, tip_node) ==
          Approx(1.1).epsilon(1e-15));  // root 0.1 m + 1 m
  scene::ContactSpec c;
  c.law.linear = true;
  c.law.stiffness = 2e4;
  c.law.damping = 20.0;
  c.friction.mu = 0.3;
  c.friction.v_reg = 0.01;
  contact::ContactPair tip = contact::ContactPair::sphere_plane(
      0, d.flexible->modal.p_BoNode_B.col(tip_node), 0.02, p_WQ, n_W);
  tip.node_b.node = tip_node;  // build_model fills Φ_k (scene_spec.hpp)
  c.pairs = {tip};
  c.name = "tip";
  spec.contacts.push_back(c);
  c.pairs = {
      contact::ContactPair::sphere_plane(0, Eigen::Vector3d(0.0, 0.0, -0.05), 0.1, p_WQ, n_W)};
  c.name = "hub";
  spec.contacts.push_back(c);
  scene::PotentialSpec field;
  field.alpha = 0.5;
  field.beta = 0.01;
  field.p_WM = Eigen::Vector3d(0.0, 0.0, height + 2.0);
  field.charges = {{0, Eigen::Vector3d(0.0, 0.1, 0.0), 1.0},
                   {0, Eigen::Vector3d(0.05, 0.0, 0.0), 2.0}};
  spec.potentials.push_back(field);
  return spec;
}

TEST_CASE("the flexible body in extended/quad agrees with core::Model at random states",
          "[precision]") {
  for (const auto formulation :
       {core::FlexibleFormulation::kCoupled, core::FlexibleFormulation::kLte}) {
    CAPTURE(core::to_string(formulation));
    for (const char* file :
         {"scenes/flexible_spinner.toml", "scenes/rotating_cantilever.toml",
          "scenes/rotating_cantilever_stiff.toml", "scenes/spin_up_beam_stiff_2.toml",
          "scenes/spin_up_beam.toml", "scenes/flexible_spinner_64.toml"}) {
      CAPTURE(file);
      // t = 0.2 inside the spinner's torque pulse and the beams' spin-up; t = 20 s after it.
      check_against_core_model(spec_of(file), formulation, 0.2, {});
      check_against_core_model(spec_of(file), formulation, 20.0, {});
    }
    CAPTURE("loaded spinner");
    check_against_core_model(loaded_spinner(false), formulation, 0.3, {});
    check_against_core_model(loaded_spinner(true), formulation, 0.3, {});
  }
}

TEST_CASE("gap supports on the flexible body agree with core::Model at random states",
          "[precision]") {
  // tube_support_impact (circular, Hunt–Crossley, friction; the frame fixed), the same spinning
  // about the tube's axis (the node's velocity has ω × r), the same swinging about z at
  // 0.5 rad/s (the node leaves the support's axis with the law's angle: the gap depends on t;
  // early, while the swing is below the clearance), and the free spinner in a planar linear
  // support. q_f ~ 1.5e-3 puts the supported node about the clearance (1 mm: the modes are
  // mass-normalized, Φ at mid-span ~1.6/√kg), so some states push and some do not; both must
  // happen, or the check would not see the contact force. Every call draws its own states.
  scene::SceneSpec fixed = spec_of("scenes/tube_support_impact.toml");
  scene::SceneSpec spinning = fixed;
  spinning.bodies[0].description.prescribed.axis_W = Eigen::Vector3d::UnitX();
  spinning.bodies[0].description.prescribed.law.rate = 3.0;  // rad/s
  scene::SceneSpec swinging = fixed;
  swinging.bodies[0].description.prescribed.law.rate = 0.5;  // rad/s about z
  int pushed = 0, checked = 0;
  unsigned seed = 100;
  for (const auto formulation :
       {core::FlexibleFormulation::kCoupled, core::FlexibleFormulation::kLte}) {
    CAPTURE(core::to_string(formulation));
    for (const double t : {0.0031, 0.4}) {
      pushed += check_against_core_model(fixed, formulation, t, {.q = 1.5e-3}, ++seed);
      pushed += check_against_core_model(spinning, formulation, t, {.q = 1.5e-3}, ++seed);
      pushed += check_against_core_model(spinner_in_planar_support(), formulation, t, {.q = 4e-3},
                                         ++seed);
      checked += 12;
    }
    // At 3.1 ms the swing has moved the node 0.8 mm across the axis.
    pushed += check_against_core_model(swinging, formulation, 0.0031, {.q = 1.5e-3}, ++seed);
    checked += 4;
  }
  INFO(pushed << " of " << checked << " random states in contact");
  CHECK(pushed > checked / 6);
  CHECK(pushed < checked);
}

TEST_CASE("sphere contacts and potentials on the flexible body agree with core::Model",
          "[precision]") {
  // Bo 3 m up and the plane 0.5 m below it: the random states (Br within ±1 m, any attitude,
  // q_f ~ 0.05 moving the tip by ~20 cm: |Φ_tip| ~ 4/√kg) put the tip sphere and the hub's
  // through the plane in some states and not in others; the charges stay above the wall
  // (z > 1.8 m). Each sphere must push somewhere and not everywhere, or the check would not see
  // its force.
  int pushed = 0, checked = 0;
  std::map<std::string, int> by_channel;
  unsigned seed = 300;
  for (const auto formulation :
       {core::FlexibleFormulation::kCoupled, core::FlexibleFormulation::kLte}) {
    CAPTURE(core::to_string(formulation));
    for (int k = 0; k < 4; ++k) {
      pushed += check_against_core_model(spinner_on_plane_in_field(3.0, 2.5), formulation, 0.3,
                                         {.q = 0.05}, ++seed, &by_channel);
      checked += 4;
    }
  }
  INFO(by_channel["tip.fn"] << " and " << by_channel["hub.fn"] << " of " << checked
                            << " random states with the tip and the hub in contact");
  CHECK(by_channel["tip.fn"] > 0);
  CHECK(by_channel["tip.fn"] < checked);
  CHECK(by_channel["hub.fn"] > 0);
  CHECK(by_channel["hub.fn"] < checked);
}

TEST_CASE("a flexible body dropped on a plane in a field: impacts and energy balance in quad",
          "[precision]") {
  // The spinner falls 0.3 m (Bo at 0.45 m, the hub sphere's bottom at 0.3 m, ~0.25 s); the
  // tilted plane and its spin make the hub strike once and the tip three times, sliding with
  // friction, while the field pulls. Quad at rtol 1e-28 closes its energy balance E − E0 + W_d
  // (modal damping, contact dissipation) to its own accuracy: E ~ 50 J (m g h, 11 kg at 0.45 m),
  // ~1e-32 J of rounding per step over ~1e4 steps and the located events' 1e-28 J (measured 5e-29
  // J); bound 1e-25 J. A plane normal left as double stored it (|n| − 1 ~ 1e-16) let friction work
  // along n: 2.5e-13 J (core/unit_vector_tpl.hpp).
  scene::SceneSpec spec = spinner_on_plane_in_field(0.45, 0.0);
  spec.end_time = 0.5;
  const std::vector<double> times = core::output_times(spec.end_time, 0.05);
  const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  const std::vector<std::string>& last = run.text.back();
  const auto at_end = [&](const std::string& name) { return std::stod(last[column(run, name)]); };
  const std::size_t balance = column(run, "energy_balance");
  INFO("impacts " << at_end("tip.impacts") << " + " << at_end("hub.impacts") << ", wear work "
                  << at_end("tip.wear_work") << " + " << at_end("hub.wear_work")
                  << " J, energy balance " << last[balance] << " J, events " << run.events.size());
  CHECK(at_end("tip.impacts") + at_end("hub.impacts") >= 1.0);
  CHECK(at_end("tip.wear_work") + at_end("hub.wear_work") > 0.0);
  Quad worst(0);
  for (const std::vector<std::string>& row : run.text) {
    worst = std::max(worst, Quad(abs(Quad(row[balance]))));
  }
  CHECK(static_cast<double>(worst) < 1e-25);
}

TEST_CASE("the tube in extended precision: impacts, wear work and energy balance", "[precision]") {
  // tube_support_impact over 50 ms (9 impacts) in extended and by CVODE at rtol 1e-12:
  // the impacts counted at the located onsets equal the double reference's count, the wear
  // work agrees to the double reference's accuracy (its estimate is ~1e-11 m in the points; the
  // wear work, 0.063 J here, to ~1e-9 relative; bound 1e-6), and extended's energy balance
  // closes to its own accuracy (E ~ 0.1 J, ~1e-16 relative per step over ~1e3 steps; bound
  // 1e-12 J) where the double one shows CVODE's error.
  scene::SceneSpec spec = spec_of("scenes/tube_support_impact.toml");
  spec.end_time = 0.05;
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun ext = solve_high_precision(spec, times, Precision::kExtended, 1e-16);
  const core::Model model = scene::build_model(spec);
  reference::SolverOptions o;
  o.rtol = 1e-12;
  const trajectory::CertifiedReference d = trajectory::certified_reference(
      model, times, "cvode", o, "rotation+points", {.use_exact_solution = false});
  const auto at = [&](const std::string& name) {
    const auto c = static_cast<std::size_t>(
        std::find(ext.columns.begin(), ext.columns.end(), name) - ext.columns.begin());
    REQUIRE(c < ext.columns.size());
    REQUIRE(d.table.columns[c] == name);
    return std::pair{ext.table.rows.back()[c], d.table.rows.back()[c]};
  };
  const auto [impacts_ext, impacts_double] = at("support.impacts");
  const auto [wear_ext, wear_double] = at("support.wear_work");
  const auto [balance_ext, balance_double] = at("energy_balance");
  INFO("impacts " << impacts_ext << " / " << impacts_double << ", wear work " << wear_ext << " / "
                  << wear_double << " J, energy balance " << balance_ext << " / " << balance_double
                  << " J");
  CHECK(impacts_ext >= 3.0);
  CHECK(impacts_ext == impacts_double);
  CHECK(wear_ext > 1e-3);
  CHECK(std::abs(wear_ext - wear_double) <= 1e-6 * wear_ext);
  CHECK(std::abs(balance_ext) <= 1e-12);
}

TEST_CASE("double, extended and quad agree in that order on flexible bodies",
          "[precision][long_quad]") {
  // Over 0.5 s (the whole horizons: tests/precision/precision_order_study_test.cpp).
  for (const char* file : kFlexibleScenes) check_precision_order(file, 0.5);
  check_precision_order("scenes/rotating_cantilever_stiff.toml", 0.5,
                        core::FlexibleFormulation::kLte);
  // The tube in its gap support over its first 30 ms: an onset with the clamp acting, releases
  // and a second impact (events at 9.5, 11.0, 14.0 … 22 ms); quad takes ~5 s per solve.
  check_precision_order("scenes/tube_support_impact.toml", 0.03);
  // The spinner dropped on a tilted plane in a point-charge field: the hub sphere strikes once
  // and the tip sphere three times, with the clamp and friction (12 events).
  check_precision_order(spinner_on_plane_in_field(0.45, 0.0), 0.5);
}

TEST_CASE("the free flexible body conserves its energy in quad once the torque is off",
          "[precision]") {
  // flexible_spinner: the sin² torque pulse ends at t = 0.5 s; from then on the coupled model
  // conserves T + ½ qᵀKq exactly (no damping, no load). Bulirsch–Stoer at rtol 1e-28 keeps it
  // to the sum of its local errors and roundings, some 1e-28 × 1e3 steps at worst (measured:
  // 8.3e-31); the bound 1e-25 is 1e10 below what a double solution could show.
  scene::SceneSpec spec = spec_of("scenes/flexible_spinner.toml");
  spec.end_time = 1.5;
  const std::vector<double> times = core::output_times(spec.end_time, 0.1);
  const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  const auto energy = static_cast<std::size_t>(
      std::find(run.columns.begin(), run.columns.end(), "energy") - run.columns.begin() - 1);
  REQUIRE(energy + 1 < run.columns.size());
  const std::size_t after_pulse = 6;  // t = 0.6
  // Tolerance: the output time 6 × 0.1 (core::output_times): one product's rounding (≤ 1.1e-16),
  // far inside 1e-14.
  REQUIRE(run.table.rows[after_pulse][0] == Approx(0.6).epsilon(1e-14));
  const Quad e0(run.text[after_pulse][energy]);
  Quad worst(0);
  for (std::size_t r = after_pulse; r < run.text.size(); ++r) {
    worst = std::max(worst, Quad(abs(Quad(run.text[r][energy]) - e0) / e0));
  }
  INFO("relative energy drift " << static_cast<double>(worst));
  CHECK(static_cast<double>(worst) < 1e-25);
  // During the pulse the torque does work: the energy changes by O(1) (a check that can fail).
  const Quad e_start(run.text.front()[energy]);
  CHECK(static_cast<double>(abs(e0 - e_start) / e0) > 1e-2);
}

}  // namespace
}  // namespace flexref::precision
