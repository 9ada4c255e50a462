/// \file flexible_scene_test.cpp
/// Flexible bodies in scene files: [body.beam], modal = "file.toml", q0/qd0, node points,
/// motion = "prescribed"; the bundled flexible scenes against the models built in code
/// (tests/support/flexible_models.hpp); every error class naming file, line and key; and the
/// trajectory CSV columns of flexible and prescribed bodies (write → read round trip).
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "core/error.hpp"
#include "flexible/beam_model.hpp"
#include "scene/build_model.hpp"
#include "scene/modal_data_reader.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/scene_error_checks.hpp"
#include "tests/support/temp_dir.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
namespace {

using testing::replace_first;
using testing::require_scene_error;

using Catch::Matchers::Contains;

// Lines 1-4.
const std::string kFlexibleSceneHead =
    "[scene]\n"
    "name = \"t\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n";
// Lines 5-8: a free hub; body-level additions go between it and the beam table.
const std::string kHub =
    "[[body]]\n"
    "name = \"f\"\n"
    "mass = 10.0\n"
    "inertia = [0.5, 0.5, 1.0]\n";
// Header on the line after the additions; with none: [body.beam] 9, length 10, elements 11,
// EA 12, EI 13, rho_A 14, modes 15, additions from 16.
const std::string kBeam =
    "[body.beam]\n"
    "length = 1.0\n"
    "elements = 4\n"
    "EA = 1e5\n"
    "EI = 3.2\n"
    "rho_A = 1.0\n"
    "modes = 2\n";

std::string flexible(const std::string& body_extra = "", const std::string& beam_extra = "") {
  return kFlexibleSceneHead + kHub + body_extra + kBeam + beam_extra;
}

// Accelerations at the initial state.
core::Accelerations initial_accelerations(const core::Model& model) {
  core::Workspace ws = model.make_workspace();
  core::Accelerations acc = model.make_accelerations();
  model.compute_accelerations(core::LoadContext{0.0, 0.0}, model.initial_state(), ws, acc);
  return acc;
}

// The same body, as far as the integrators see it: mass, inertia, modes and accelerations.
void check_same_model(const core::Model& read, const core::Model& built) {
  REQUIRE(read.num_bodies() == built.num_bodies());
  CHECK(read.formulation() == built.formulation());
  for (int i = 0; i < read.num_bodies(); ++i) {
    const core::Body& a = read.body(i);
    const core::Body& b = built.body(i);
    CHECK(a.motion() == b.motion());
    CHECK(a.mass() == Approx(b.mass()).epsilon(1e-14));
    CHECK((a.I_Br_B() - b.I_Br_B()).norm() <= 1e-13 * b.I_Br_B().norm());
    REQUIRE(a.mode_count() == b.mode_count());
    CHECK((a.natural_frequencies() - b.natural_frequencies()).norm() <=
          1e-13 * b.natural_frequencies().norm());
    const auto& pa = a.description().points;
    const auto& pb = b.description().points;
    REQUIRE(pa.size() >= 1);
    CHECK(pa[0].name == "tip");
    CHECK(pa[0].node == pb[0].node);
    CHECK(pa[0].p_BoP_B == pb[0].p_BoP_B);
  }
  const core::State sa = read.initial_state();
  const core::State sb = built.initial_state();
  const core::Accelerations aa = initial_accelerations(read);
  const core::Accelerations ab = initial_accelerations(built);
  for (std::size_t i = 0; i < sa.size(); ++i) {
    CHECK((sa[i].q_f - sb[i].q_f).norm() == 0.0);
    CHECK((sa[i].w_WB_B - sb[i].w_WB_B).norm() == 0.0);
    CHECK((aa[i].qdd_f - ab[i].qdd_f).norm() <= 1e-10 * (1.0 + ab[i].qdd_f.norm()));
    CHECK((aa[i].alpha_WB_B - ab[i].alpha_WB_B).norm() <= 1e-10 * (1.0 + ab[i].alpha_WB_B.norm()));
  }
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

}  // namespace

TEST_CASE("bundled flexible scenes equal the models built in code", "[app][scene][flexible]") {
  using core::FlexibleFormulation;
  SECTION("flexible_spinner") {
    for (const FlexibleFormulation f : {FlexibleFormulation::kCoupled, FlexibleFormulation::kLte}) {
      const scene::Scene s = scene::read_scene("scenes/flexible_spinner.toml", f);
      CHECK(s.end_time == 10.0);
      CHECK(s.output_step == 0.01);
      check_same_model(*s.model, testing::flexible_spinner_model(f));
      const auto& points = s.model->body(0).description().points;
      REQUIRE(points.size() == 2);
      CHECK(points[1].name == "hub_rim");
      CHECK(points[1].node == -1);
      CHECK(points[1].p_BoP_B == Eigen::Vector3d(0.0, 0.1, 0.0));
      CHECK(s.model->discontinuities() == std::vector<double>{0.0, 0.5});
    }
  }
  SECTION("rotating_cantilever") {
    const scene::Scene s = scene::read_scene("scenes/rotating_cantilever.toml");
    const Eigen::Vector4d q0(0.01, 0.01, 0.0, 0.0);
    check_same_model(*s.model, testing::rotating_cantilever_model(
                                   core::FlexibleFormulation::kCoupled, 3.0, 4, 10, q0));
    CHECK(s.model->body(0).description().prescribed.law.kind ==
          core::AngleLaw::Kind::kConstantRate);
  }
  SECTION("spin_up_beam and its variants") {
    for (const auto& [name, rate] : {std::pair<std::string, double>{"spin_up_beam", 2.0},
                                     {"spin_up_beam_4", 4.0},
                                     {"spin_up_beam_6", 6.0}}) {
      INFO(name);
      const scene::Scene s = scene::read_scene("scenes/" + name + ".toml");
      CHECK(s.end_time == 30.0);
      check_same_model(*s.model,
                       testing::spin_up_beam_model(core::FlexibleFormulation::kCoupled, rate));
      const core::PrescribedRotation& p = s.model->body(0).description().prescribed;
      CHECK(p.law.kind == core::AngleLaw::Kind::kSpinUp);
      CHECK(p.law.rate == rate);
      CHECK(p.law.spin_up_time == 15.0);
      CHECK(p.axis_W == Eigen::Vector3d::UnitZ());
    }
  }
}

TEST_CASE("flexible body keys", "[app][scene][flexible]") {
  SECTION("beam defaults: all three families, clamped-free, no damping, zero q0") {
    const scene::Scene s = scene::parse_scene(flexible(), "f.toml");
    const core::Body& b = s.model->body(0);
    REQUIRE(b.is_flexible());
    CHECK(b.mode_count() == 2);
    const flexible::ModalData& m = b.description().flexible->modal;
    CHECK(m.node_count() == 17);  // 4 elements × 4 Gauss–Lobatto points + 1
    CHECK(m.damping_ratio.isZero(0.0));
    CHECK(m.mode_names[0] == "bending-xy-1");
    CHECK(s.model->initial_state()[0].q_f.isZero(0.0));
  }
  SECTION("EI_y, EI_z, GJ, origin, free-free, families, damping (scalar and array)") {
    const std::string beam_extra =
        "origin = [0.2, 0.0, 0.0]\nboundary = \"free-free\"\nfamilies = [\"axial\", "
        "\"bending-xz\"]\nGJ = 2.0\n";
    const std::string text =
        replace_first(flexible("", beam_extra), "EI = 3.2\n", "EI_y = 3.2\nEI_z = 6.4\n");
    const scene::Scene s = scene::parse_scene(text + "damping_ratio = 0.02\n", "f.toml");
    const flexible::ModalData& m = s.model->body(0).description().flexible->modal;
    REQUIRE_FALSE(m.mode_names.empty());
    for (const std::string& name : m.mode_names) CHECK_FALSE(name.starts_with("bending-xy"));
    // Tolerance: the origin's 0.2 plus the root node's x = 0 (one rounding at most).
    CHECK(m.p_BoNode_B.row(0).minCoeff() == Approx(0.2).epsilon(1e-15));
    CHECK(m.damping_ratio.isConstant(0.02));
    flexible::BeamParameters p;
    p.origin = Eigen::Vector3d(0.2, 0.0, 0.0);
    p.length = 1.0;
    p.elements = 4;
    p.EA = 1e5;
    p.EI_y = 3.2;
    p.EI_z = 6.4;
    p.GJ = 2.0;
    p.rho_A = 1.0;
    p.boundary = flexible::BeamBoundary::kFreeFree;
    const flexible::ModalData expected =
        flexible::make_beam_modal_data(p, 2, flexible::BeamModeFilter{true, false, true});
    CHECK(m.stiffness == expected.stiffness);
    const scene::Scene s2 = scene::parse_scene(text + "damping_ratio = [0.01, 0.03]\n", "f.toml");
    CHECK(s2.model->body(0).description().flexible->modal.damping_ratio ==
          Eigen::Vector2d(0.01, 0.03));
  }
  SECTION("q0, qd0 and node points") {
    const scene::Scene s =
        scene::parse_scene(flexible("q0 = [0.01, -0.02]\nqd0 = [0.5, 0]\npoints = [{ name = "
                                    "\"tip\", node = \"node4\" }, { name = \"rim\", at = "
                                    "[0, 0.1, 0] }]\n"),
                           "f.toml");
    const core::BodyState s0 = s.model->initial_state()[0];
    CHECK(s0.q_f == Eigen::Vector2d(0.01, -0.02));
    CHECK(s0.qd_f == Eigen::Vector2d(0.5, 0.0));
    const auto& points = s.model->body(0).description().points;
    CHECK(points[0].node == 16);
    CHECK(points[0].p_BoP_B == Eigen::Vector3d(1.0, 0.0, 0.0));
    CHECK(points[1].node == -1);
    // The node point is deformed: it moves by Φ_tip q0.
    const Eigen::Vector3d deformed = s.model->p_WP(0, s0, points[0]);
    const Eigen::Vector3d undeformed = s.model->p_WP(0, s0, points[0].p_BoP_B);
    CHECK((deformed - undeformed).norm() > 1e-3);
  }
  SECTION("prescribed motion: no hub, axis renormalized within 1e-6, spin-up law") {
    const std::string text = kFlexibleSceneHead +
                             "[[body]]\nname = \"f\"\nmotion = \"prescribed\"\n"
                             "prescribed = { axis = [0, 0, 1.0000001], law = \"spin-up\", rate = "
                             "2, spin_up_time = 15 }\n" +
                             kBeam;
    const scene::Scene s = scene::parse_scene(text, "f.toml");
    const core::Body& b = s.model->body(0);
    CHECK(b.is_prescribed());
    CHECK(b.description().mass == 0.0);
    CHECK(b.description().prescribed.axis_W.norm() == Approx(1.0).epsilon(1e-15));
    CHECK(b.description().prescribed.law.kind == core::AngleLaw::Kind::kSpinUp);
    CHECK(b.description().prescribed.law.spin_up_time == 15.0);
  }
  SECTION("the formulation is the caller's choice") {
    CHECK(scene::parse_scene(flexible(), "f.toml").model->formulation() ==
          core::FlexibleFormulation::kCoupled);
    CHECK(scene::parse_scene(flexible(), "f.toml", core::FlexibleFormulation::kLte)
              .model->formulation() == core::FlexibleFormulation::kLte);
  }
}

TEST_CASE("geometric_stiffening = true attaches the beam's geometric stiffness",
          "[app][scene][flexible]") {
  const scene::Scene plain = scene::parse_scene(flexible(), "f.toml");
  CHECK_FALSE(plain.model->body(0).invariants().geometric.has_value());
  CHECK_FALSE(plain.spec.bodies[0].beam->geometric_stiffening);
  const scene::Scene stiff =
      scene::parse_scene(flexible("", "geometric_stiffening = true\n"), "f.toml");
  REQUIRE(stiff.model->body(0).invariants().geometric.has_value());
  CHECK(stiff.spec.bodies[0].beam->geometric_stiffening);
  // A beam along x: E_x positive definite on the bending modes, E_y = E_z = 0.
  const auto& g = *stiff.model->body(0).invariants().geometric;
  CHECK(g.E[0].llt().info() == Eigen::Success);
  CHECK(g.E[1].norm() == 0.0);
  CHECK(g.E_nonzero == std::vector<int>{0});
  // Regenerating the modes (a study editing the beam) keeps the option.
  scene::BodySpec body = stiff.spec.bodies[0];
  scene::regenerate_beam_modes(body);
  CHECK(body.description.flexible->modal.geometric.has_value());
}

TEST_CASE("modal = \"file.toml\" is read relative to the scene", "[app][scene][flexible]") {
  const testing::TempDir tmp("flexible-scene");
  const std::filesystem::path& dir = tmp.path();
  std::filesystem::create_directories(dir / "sub");
  flexible::BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  p.length = 1.0;
  p.elements = 4;
  p.EA = 1e5;
  p.EI_y = p.EI_z = 3.2;
  const flexible::ModalData data = flexible::make_beam_modal_data(p, 3);
  scene::write_modal_data(data, (dir / "sub" / "m.toml").string());
  const std::string body =
      kFlexibleSceneHead + kHub + "points = [{ name = \"tip\", node = \"node4\" }]\n";

  SECTION("a good file") {
    write_text(dir / "scene.toml", body + "modal = \"sub/m.toml\"\n");
    const scene::Scene s = scene::read_scene((dir / "scene.toml").string());
    CHECK(s.model->body(0).mode_count() == 3);
    CHECK(s.model->body(0).description().points[0].node == 16);
  }
  SECTION("a missing file is reported at the scene key") {
    write_text(dir / "scene.toml", body + "modal = \"sub/none.toml\"\n");
    try {
      (void)scene::read_scene((dir / "scene.toml").string());
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.file() == (dir / "scene.toml").string());
      CHECK(e.line() == 10);
      CHECK(e.key() == "body[1].modal");
      CHECK_THAT(e.what(), Contains("cannot open the modal-data file"));
    }
  }
  SECTION("errors inside the file name that file, its line and key, and the scene key") {
    write_text(dir / "sub" / "bad.toml",
               "format = \"flexref-modal-data\"\nversion = 1\nnodes = [{ mass = -1.0, position "
               "= [0, 0, 0] }]\n");
    write_text(dir / "scene.toml", body + "modal = \"sub/bad.toml\"\n");
    try {
      (void)scene::read_scene((dir / "scene.toml").string());
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.file() == (dir / "sub" / "bad.toml").string());
      CHECK(e.line() == 3);
      CHECK(e.key() == "nodes[1].mass");
      CHECK_THAT(e.what(), Contains("bad.toml:3: key 'nodes[1].mass'"));
      CHECK_THAT(e.what(), Contains("modal data of body[1].modal"));
    }
  }
}

TEST_CASE("bad flexible input is an InputError naming file, line and key",
          "[app][scene][flexible]") {
  SECTION("missing key") {
    require_scene_error(replace_first(flexible(), "length = 1.0\n", ""), 9, "body[1].beam.length",
                        "required key is missing");
    require_scene_error(replace_first(flexible(), "EI = 3.2\n", ""), 9, "body[1].beam.EI",
                        "or EI_y and EI_z");
    require_scene_error(replace_first(flexible(), "EI = 3.2\n", "EI_y = 3.2\n"), 9,
                        "body[1].beam.EI_z", "required key is missing");
    require_scene_error(flexible("motion = \"prescribed\"\n"), 5, "body[1].prescribed",
                        "required table is missing");
    require_scene_error(flexible("motion = \"prescribed\"\n"
                                 "prescribed = { law = \"constant-rate\", rate = 1 }\n"),
                        10, "body[1].prescribed.axis", "required key is missing");
    require_scene_error(
        flexible("motion = \"prescribed\"\n"
                 "prescribed = { axis = [0, 0, 1], law = \"spin-up\", rate = 1 }\n"),
        10, "body[1].prescribed.spin_up_time", "positive spin-up time");
  }
  SECTION("wrong type") {
    require_scene_error(replace_first(flexible(), "elements = 4\n", "elements = 1.5\n"), 11,
                        "body[1].beam.elements", "got 1.5 (a number)");
    require_scene_error(replace_first(flexible(), "modes = 2\n", "modes = \"2\"\n"), 15,
                        "body[1].beam.modes", "positive integer mode count");
    require_scene_error(flexible("", "families = \"axial\"\n"), 16, "body[1].beam.families",
                        "got \"axial\" (a string)");
    require_scene_error(kFlexibleSceneHead + kHub + "beam = 1.0\n", 9, "body[1].beam",
                        "got 1.0 (a number)");
    require_scene_error(kFlexibleSceneHead + kHub + "modal = 1\n", 9, "body[1].modal",
                        "path of a modal-data file");
    require_scene_error(flexible("q0 = [0.1, \"x\"]\n"), 9, "body[1].q0", "got \"x\" (a string)");
  }
  SECTION("bad values") {
    require_scene_error(flexible("", "families = [\"bending-xy\", \"twist\"]\n"), 16,
                        "body[1].beam.families", "got \"twist\" (a string)");
    require_scene_error(flexible("", "families = [\"torsion\"]\n"), 16, "body[1].beam.families",
                        "torsion modes do not move the beam axis");
    require_scene_error(flexible("", "families = [\"axial\", \"axial\"]\n"), 16,
                        "body[1].beam.families", "listed twice");
    require_scene_error(flexible("", "boundary = \"pinned\"\n"), 16, "body[1].beam.boundary",
                        "\"clamped-free\", \"free-free\"");
    require_scene_error(flexible("", "geometric_stiffening = \"yes\"\n"), 16,
                        "body[1].beam.geometric_stiffening", "true or false");
    require_scene_error(flexible("", "boundary = \"free-free\"\ngeometric_stiffening = true\n"), 17,
                        "body[1].beam.geometric_stiffening", "clamped-free");
    require_scene_error(replace_first(flexible(), "elements = 4\n", "elements = 0\n"), 11,
                        "body[1].beam.elements", "1 to 500");
    require_scene_error(replace_first(flexible(), "EA = 1e5\n", "EA = -1\n"), 12, "body[1].beam.EA",
                        "positive axial stiffness");
    require_scene_error(replace_first(flexible(), "modes = 2\n", "modes = 100\n"), 15,
                        "body[1].beam.modes", "cannot make the beam's modal data");
    require_scene_error(flexible("", "EI_y = 1.0\n"), 16, "body[1].beam.EI_y", "either EI or EI_y");
    require_scene_error(flexible("", "damping_ratio = -0.1\n"), 16, "body[1].beam.damping_ratio",
                        "damping ratio >= 0");
    require_scene_error(flexible("", "damping_ratio = [0.1]\n"), 16, "body[1].beam.damping_ratio",
                        "an array of 2");
    require_scene_error(flexible("", "colour = 1\n"), 16, "body[1].beam.colour", "unknown key");
  }
  SECTION("unknown node names and node points on rigid bodies") {
    require_scene_error(flexible("points = [{ name = \"tip\", node = \"node9\" }]\n"), 9,
                        "body[1].points[1].node", "no node named \"node9\"");
    require_scene_error(
        flexible("points = [{ name = \"tip\", node = \"node4\", at = [1, 0, 0] }]\n"), 9,
        "body[1].points[1].at", "either at or node");
    require_scene_error(
        kFlexibleSceneHead + kHub + "points = [{ name = \"p\", node = \"node1\" }]\n", 9,
        "body[1].points[1].node", "applies only to flexible bodies");
  }
  SECTION("initial modal coordinates") {
    require_scene_error(flexible("q0 = [0.1]\n"), 9, "body[1].q0", "an array of 2");
    require_scene_error(flexible("qd0 = [0.1, 0.2, 0.3]\n"), 9, "body[1].qd0", "an array of 2");
    require_scene_error(kFlexibleSceneHead + kHub + "q0 = [0.1]\n", 9, "body[1].q0",
                        "applies only to flexible bodies");
  }
  SECTION("hub mass and inertia") {
    require_scene_error(
        kFlexibleSceneHead + "[[body]]\nname = \"b\"\nmass = 0\ninertia = [1, 1, 1]\n", 7,
        "body[1].mass", "allowed only for the hub of a flexible body");
    require_scene_error(
        kFlexibleSceneHead + "[[body]]\nname = \"f\"\nmass = 0.0\ninertia = [1, 1, 1]\n" + kBeam, 8,
        "body[1].inertia", "no inertia with mass = 0");
    require_scene_error(kFlexibleSceneHead + "[[body]]\nname = \"f\"\nmass = -1.0\n" + kBeam, 7,
                        "body[1].mass", "hub mass >= 0");
    // A free beam without hub has no inertia about its own axis.
    require_scene_error(kFlexibleSceneHead + "[[body]]\nname = \"f\"\n" + kBeam, 5, "body[1].mass",
                        "add a hub");
  }
  SECTION("prescribed motion") {
    require_scene_error(kFlexibleSceneHead +
                            "[[body]]\nname = \"b\"\nmass = 1\ninertia = [1, 1, 1]\n"
                            "motion = \"prescribed\"\n",
                        9, "body[1].motion", "applies only to flexible bodies");
    const std::string law = "prescribed = { axis = [0, 0, 1], law = \"constant-rate\", rate = 3";
    require_scene_error(flexible("motion = \"prescribed\"\n" + law + ", spin_up_time = 1 }\n"), 10,
                        "body[1].prescribed.spin_up_time", "applies only to law = \"spin-up\"");
    require_scene_error(flexible("motion = \"prescribed\"\nprescribed = { axis = [0, 0, 2], law = "
                                 "\"constant-rate\", rate = 3 }\n"),
                        10, "body[1].prescribed.axis", "got norm 2");
    require_scene_error(flexible("motion = \"prescribed\"\nprescribed = { axis = [0, 0, 1], law = "
                                 "\"spin\", rate = 3 }\n"),
                        10, "body[1].prescribed.law", "\"constant-rate\", \"spin-up\"");
    require_scene_error(flexible(law + " }\n"), 9, "body[1].prescribed",
                        "applies only to motion = \"prescribed\"");
    require_scene_error(
        flexible("motion = \"prescribed\"\n" + law + " }\nangular_velocity = [0, 0, 1]\n"), 11,
        "body[1].angular_velocity", "follows from its law");
    require_scene_error(flexible("motion = \"prescribed\"\n" + law + " }\nvelocity = [1, 0, 0]\n"),
                        11, "body[1].velocity", "frame origin is fixed");
  }
  SECTION("beam and modal together") {
    require_scene_error(flexible("modal = \"m.toml\"\n"), 9, "body[1].modal", "not both");
  }
}

TEST_CASE("gravity on a flexible body loads its modes", "[app][scene][flexible]") {
  // A free hub with a beam along x under gravity along −z: the rigid body falls with g, and
  // the modal forces Sᵀ Aᵀ g load the out-of-plane (xz) bending modes, not the in-plane ones.
  // The falling frame carries the same uniform field, so the free body's modes see only the
  // difference between the nodes' g and the frame's acceleration: zero for translation. The
  // rotation rows see the torque of gravity about the undeformed centre of mass: zero. So the
  // modal accelerations vanish to round-off, while the frame falls with g.
  const scene::Scene s =
      scene::parse_scene(replace_first(kFlexibleSceneHead, "output_step = 0.1\n",
                                       "output_step = 0.1\ngravity = [0, 0, -9.81]\n") +
                             kHub + kBeam + "families = [\"bending-xz\"]\n",
                         "g.toml");
  const core::Accelerations acc = initial_accelerations(*s.model);
  CHECK(acc[0].a_WBr.isApprox(Eigen::Vector3d(0.0, 0.0, -9.81), 1e-12));
  // Round-off: terms of size g·μ with unit modal masses, ~1e-15·10.
  CHECK(acc[0].qdd_f.cwiseAbs().maxCoeff() < 1e-12);
  CHECK(acc[0].alpha_WB_B.norm() < 1e-12);
}

TEST_CASE("trajectory CSV of flexible and prescribed bodies: columns and round trip",
          "[app][scene][flexible][csv]") {
  const scene::Scene s = scene::read_scene("scenes/rotating_cantilever.toml");
  const core::Model& model = *s.model;
  core::Trajectory trajectory;
  for (int k = 0; k < 3; ++k) {
    const double t = 0.1 * k;
    core::State state = model.initial_state();
    model.apply_prescribed_motion(t, state);
    state[0].q_f = Eigen::Vector4d(0.01, -0.02, 0.003, 0.0) * (k + 1);
    state[0].qd_f = Eigen::Vector4d(0.1, 0.2, -0.3, 0.4) * (k + 1);
    trajectory.times.push_back(t);
    trajectory.states.push_back(state);
  }
  const trajectory::TrajectoryTable table = trajectory::tabulate(model, trajectory);
  const std::vector<std::string> expected_tail = {
      "beam.W3",  "beam.tip.x", "beam.tip.y",        "beam.tip.z", "beam.q1",
      "beam.q2",  "beam.q3",    "beam.q4",           "beam.qd1",   "beam.qd2",
      "beam.qd3", "beam.qd4",   "beam.drive_torque", "energy"};
  REQUIRE(table.columns.size() == 1 + 13 + expected_tail.size() - 1);
  CHECK(std::vector<std::string>(table.columns.end() - static_cast<long>(expected_tail.size()),
                                 table.columns.end()) == expected_tail);
  const std::size_t row = 2;
  const core::BodyState& st = trajectory.states[row][0];
  CHECK(table.rows[row][static_cast<std::size_t>(table.column("beam.q3"))] == st.q_f(2));
  CHECK(table.rows[row][static_cast<std::size_t>(table.column("beam.qd4"))] == st.qd_f(3));
  // The tip is deformed (node point), and the energy includes the elastic energy.
  const core::TrackedPoint& tip = model.body(0).description().points[0];
  const Eigen::Vector3d p = model.p_WP(0, st, tip);
  CHECK(table.rows[row][static_cast<std::size_t>(table.column("beam.tip.y"))] == p.y());
  core::Workspace ws = model.make_workspace();
  const double t = trajectory.times[row];
  // Tolerance: the energy column and T + V recomputed here from the same state: sums of O(10)
  // terms over the modal coordinates in possibly different orders, each ≤ ~1e-15 relative; 1e-12
  // leaves a factor ~1000.
  CHECK(table.rows[row][static_cast<std::size_t>(table.column("energy"))] ==
        Approx(model.kinetic_energy(trajectory.states[row]) +
               model.potential_energy({t, t}, trajectory.states[row], ws))
            .epsilon(1e-12));
  CHECK(model.elastic_energy(trajectory.states[row]) > 0.0);
  // The drive torque: Model::driving_torque at the accelerations of the state.
  core::Accelerations acc = model.make_accelerations();
  const core::Loads loads = model.compute_accelerations({t, t}, trajectory.states[row], ws, acc);
  const double torque = model.driving_torque(0, loads, acc[0], ws);
  CHECK(torque != 0.0);
  CHECK(table.rows[row][static_cast<std::size_t>(table.column("beam.drive_torque"))] == torque);

  const testing::TempDir dir("flexible-round-trip");
  const auto path = dir / "round_trip.csv";
  trajectory::write_csv(table, path.string());
  const trajectory::TrajectoryTable back = trajectory::read_csv(path.string());
  CHECK(back.columns == table.columns);
  CHECK(back.rows == table.rows);
}

}  // namespace flexref::app
