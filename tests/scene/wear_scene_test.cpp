// Scene keys of the wear scenes (scenes/README.md): loads, spheres and gap supports at nodes,
// contact names and their wear columns, the harmonic profile, beam boundaries with a clamped tip —
// and the errors each refuses, at the file, line and key.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>

#include "contact/contact.hpp"
#include "contact/gap_support.hpp"
#include "core/applied_load.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/scene_error_checks.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref {
namespace {

using testing::require_scene_error;

// Lines 1-4 [scene], 5-8 the rigid body "ball", 9-22 the flexible "tube"; additions at 23.
const std::string kHead =
    "[scene]\n"
    "name = \"t\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n"
    "[[body]]\n"
    "name = \"ball\"\n"
    "mass = 1.0\n"
    "inertia = [0.1, 0.1, 0.1]\n"
    "[[body]]\n"
    "name = \"tube\"\n"
    "motion = \"prescribed\"\n"
    "[body.prescribed]\n"
    "axis = [0.0, 0.0, 1.0]\n"
    "law = \"constant-rate\"\n"
    "rate = 0.0\n"
    "[body.beam]\n"
    "length = 1.0\n"
    "elements = 4\n"
    "EI = 10.0\n"
    "EA = 1000.0\n"
    "rho_A = 1.0\n"
    "modes = 2\n";
constexpr int kFirst = 23;

const std::string kGap =
    "[[contact]]\n"
    "kind = \"gap-support\"\n"
    "name = \"support\"\n"
    "body = \"tube\"\n"
    "node = \"node2\"\n"
    "axis_point = [0.0, 0.0, 0.0]\n"
    "axis = [1.0, 0.0, 0.0]\n"
    "clearance = 0.001\n";

TEST_CASE("gap supports, node forces and harmonic profiles are read") {
  const scene::Scene s = scene::parse_scene(
      kHead + kGap +
          "[[load]]\nkind = \"force\"\nbody = \"tube\"\nnode = \"node3\"\nvalue = [0, 1, 0]\n"
          "profile = { shape = \"harmonic\", frequency = 2.0, phase = 0.5 }\n",
      "ok.toml");
  const core::Model& m = *s.model;
  REQUIRE(m.wear_channel_names() == std::vector<std::string>{"support"});
  CHECK(m.switching_function_count() == 1);
  CHECK(m.tracks_applied_work());
  const std::vector<std::string> columns = trajectory::trajectory_columns(m);
  for (const char* c : {"applied_work", "support.fn", "support.slip_speed", "support.wear_work",
                        "support.impacts"}) {
    CHECK(std::find(columns.begin(), columns.end(), c) != columns.end());
  }
  // The harmonic value: sin(2π·2·0.1 + 0.5).
  const core::TimeProfile p = core::TimeProfile::harmonic(2.0, 0.5);
  CHECK(p.value(0.1, 0.1) == Approx(std::sin(2.0 * std::numbers::pi * 0.2 + 0.5)).epsilon(1e-15));
  std::vector<double> switches;
  p.append_discontinuities(switches);
  CHECK(switches.empty());
}

TEST_CASE("sphere-plane and sphere-sphere contacts at nodes are read with the node's Φ") {
  const scene::Scene s = scene::parse_scene(
      kHead +
          "[[contact]]\nkind = \"sphere-sphere\"\nbody = \"tube\"\nnode = \"node2\"\n"
          "radius = 0.01\nbody_b = \"ball\"\ncenter_b = [0, 0, 0]\nradius_b = 0.1\n"
          "[[contact]]\nkind = \"point-plane\"\nbody = \"tube\"\nnode = \"node3\"\n"
          "plane_point = [0, 0, -0.01]\n",
      "ok.toml");
  const auto* ss = dynamic_cast<const contact::ContactElement*>(s.model->elements()[0].get());
  const auto* pp = dynamic_cast<const contact::ContactElement*>(s.model->elements()[1].get());
  REQUIRE(ss != nullptr);
  REQUIRE(pp != nullptr);
  const flexible::ModalData& modal = s.model->body(1).description().flexible->modal;
  const contact::ContactPair& a = ss->pairs().front();
  CHECK(a.node_a.deforms());
  CHECK(!a.node_b.deforms());
  CHECK(a.node_a.phi_B == modal.mode_rows(a.node_a.node));
  CHECK(a.p_BoCa_B == modal.p_BoNode_B.col(a.node_a.node));
  CHECK(modal.node_names[static_cast<std::size_t>(a.node_a.node)] == "node2");
  const contact::ContactPair& p = pp->pairs().front();
  CHECK(modal.node_names[static_cast<std::size_t>(p.node_b.node)] == "node3");
  CHECK(p.node_b.phi_B == modal.mode_rows(p.node_b.node));
  CHECK(s.model->wear_channel_count() == 0);  // unnamed contacts: no wear columns
}

TEST_CASE("clamped-clamped and clamped-pinned beams: no displacement at the ends") {
  for (const char* boundary : {"clamped-clamped", "clamped-pinned"}) {
    std::string text = kHead;
    text += "boundary = \"" + std::string(boundary) + "\"\n";
    const scene::Scene s = scene::parse_scene(text, "ok.toml");
    const flexible::ModalData& modal = s.model->body(1).description().flexible->modal;
    const int tip = modal.node_count() - 1;
    // Nodes are the Gauss-Lobatto points; the first and last are the beam's ends.
    CHECK(modal.mode_rows(0).norm() == 0.0);
    CHECK(modal.mode_rows(tip).norm() == 0.0);
    CHECK(modal.mode_rows(tip - 1).norm() > 0.0);
  }
  // The first frequencies are 22.373/L² √(EI/ρA) (clamped-clamped) and 15.418/L² √(EI/ρA)
  // (clamped-pinned), Euler–Bernoulli. Four cubic Hermite elements overestimate them by
  // O(h⁴): 1.3e-3 measured on the clamped-clamped one; 3e-3 still separates every other
  // boundary (clamped-free 3.516, pinned-pinned 9.870, free-free 22.373 but no clamped zero).
  const scene::Scene s = scene::parse_scene(kHead + "boundary = \"clamped-clamped\"\n", "ok.toml");
  CHECK(s.model->body(1).natural_frequencies()(0) ==
        Approx(22.3733 * std::sqrt(10.0)).epsilon(3e-3));
  const scene::Scene p = scene::parse_scene(kHead + "boundary = \"clamped-pinned\"\n", "ok.toml");
  CHECK(p.model->body(1).natural_frequencies()(0) ==
        Approx(15.4182 * std::sqrt(10.0)).epsilon(3e-3));
}

TEST_CASE("bad node, gap-support and profile keys are refused at their line and key") {
  require_scene_error(kHead +
                          "[[load]]\nkind = \"force\"\nbody = \"ball\"\nnode = \"node1\"\n"
                          "value = [0, 1, 0]\n",
                      kFirst + 3, "load[1].node", "applies only to flexible bodies");
  require_scene_error(kHead +
                          "[[load]]\nkind = \"force\"\nbody = \"tube\"\nnode = \"nodeX\"\n"
                          "value = [0, 1, 0]\n",
                      kFirst + 3, "load[1].node", "no node named \"nodeX\"");
  require_scene_error(kHead +
                          "[[load]]\nkind = \"force\"\nbody = \"tube\"\nnode = \"node1\"\n"
                          "at = [0, 0, 0]\nvalue = [0, 1, 0]\n",
                      kFirst + 4, "load[1].at", "either at or node");
  require_scene_error(kHead +
                          "[[load]]\nkind = \"force\"\nbody = \"tube\"\nvalue = [0, 1, 0]\n"
                          "profile = { shape = \"harmonic\", frequency = 0.0 }\n",
                      kFirst + 4, "load[1].profile.frequency", "positive frequency");
  require_scene_error(kHead +
                          "[[load]]\nkind = \"force\"\nbody = \"tube\"\nvalue = [0, 1, 0]\n"
                          "profile = { shape = \"harmonic\", frequency = 1.0, duration = 1.0 }\n",
                      kFirst + 4, "load[1].profile.duration", "applies only to pulses");
  require_scene_error(kHead + kGap + "clearance = 0.002\n", kFirst + 8, "", "");
  std::string no_clearance = kGap;
  no_clearance.erase(no_clearance.find("clearance"));
  require_scene_error(kHead + no_clearance, kFirst, "contact[1].clearance",
                      "positive radial clearance");
  require_scene_error(kHead + kGap + "shape = \"planar\"\nplane_normal = [1.0, 0.0, 0.0]\n",
                      kFirst + 9, "contact[1].plane_normal", "parallel to the axis");
  require_scene_error(kHead + kGap + "radius = 0.1\n", kFirst + 8, "contact[1].radius",
                      "does not apply to a gap support");
  require_scene_error(kHead + kGap + kGap, kFirst + 10, "contact[2].name",
                      "duplicate contact name");
  require_scene_error(
      kHead +
          "[[contact]]\nkind = \"sphere-plane\"\nbody = \"ball\"\nnode = \"node1\"\n"
          "radius = 0.1\n",
      kFirst + 3, "contact[1].node", "applies only to flexible bodies");
  require_scene_error(
      kHead +
          "[[contact]]\nkind = \"point-plane\"\nbody = \"ball\"\npoint = [0, 0, 0]\n"
          "clearance = 0.1\n",
      kFirst + 4, "contact[1].clearance", "applies only to kind = \"gap-support\"");
}

TEST_CASE("the wear metric is the relative error of each contact's final wear work") {
  trajectory::TrajectoryTable a, b;
  a.columns = b.columns = {"t", "c.wear_work", "d.wear_work"};
  a.rows = {{0.0, 0.0, 0.0}, {1.0, 2.2, 3.0}};
  b.rows = {{0.0, 0.0, 0.0}, {1.0, 2.0, 3.0}};
  const trajectory::ComparisonReport r = trajectory::compare_trajectories(a, b);
  // |2.2 − 2.0| / 2.0 = 0.1 to the representation error of 2.2 and 0.1 (a few ε): 1e-12.
  CHECK(trajectory::metric_value(r, "wear") == Approx(0.1).epsilon(1e-12));
  // With a wear law, the largest worn depth's final relative error too (here the larger). Both
  // values are one division of short decimals: 1e-12 is a few hundred round-offs.
  a.columns = b.columns = {"t", "c.wear_work", "c.wear_depth"};
  a.rows = {{0.0, 0.0, 0.0}, {1.0, 2.2, 1.5e-4}};
  b.rows = {{0.0, 0.0, 0.0}, {1.0, 2.0, 1.0e-4}};
  CHECK(trajectory::metric_value(trajectory::compare_trajectories(a, b), "wear") ==
        Approx(0.5).epsilon(1e-12));
  trajectory::TrajectoryTable plain;
  plain.columns = {"t"};
  plain.rows = {{0.0}, {1.0}};
  CHECK_THROWS_WITH(
      trajectory::metric_value(trajectory::compare_trajectories(plain, plain), "wear"),
      Catch::Matchers::Contains("named contact"));
}

}  // namespace
}  // namespace flexref
