#include "scene/scene_reader.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "tests/support/scene_error_checks.hpp"

namespace flexref::app {
namespace {

using testing::require_scene_error;

using Catch::Matchers::Contains;

// Bundled scenes are found relative to the repository root (ctest's working directory).
scene::Scene read_bundled(const std::string& name) {
  return scene::read_scene("scenes/" + name + ".toml");
}

// Loads at the initial state and t = t_segment = t (inside the first step).
core::Workspace loads_at(const core::Model& model, double t) {
  core::Workspace ws = model.make_workspace();
  const core::State state = model.initial_state();
  model.compute_wrenches(core::LoadContext{t, t}, state, ws);
  return ws;
}

// Principal inertias as a matrix; exact comparisons below are of values the file gives in
// decimal and the reader copies (or shifts once, then compared with a tolerance).
Eigen::Matrix3d diag(double a, double b, double c) { return Eigen::Vector3d(a, b, c).asDiagonal(); }

// Every accelerations entry finite at t = 0: the scene is usable as read.
bool initial_accelerations_finite(const core::Model& model) {
  core::Workspace ws = model.make_workspace();
  const core::State state = model.initial_state();
  core::Accelerations acc = model.make_accelerations();
  model.compute_accelerations(core::LoadContext{0.0, 0.0}, state, ws, acc);
  for (const core::BodyAcceleration& a : acc) {
    if (!a.a_WBr.allFinite() || !a.alpha_WB_B.allFinite()) return false;
  }
  return true;
}

// A valid minimal scene: [scene] on lines 1-4, one [[body]] on lines 5-8; additions start at
// line 9.
const std::string kMinimalScene =
    "[scene]\n"
    "name = \"t\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n";
const std::string kBody =
    "[[body]]\n"
    "name = \"b\"\n"
    "mass = 1.0\n"
    "inertia = [1.0, 2.0, 2.5]\n";

}  // namespace

TEST_CASE("bundled scenes read into the expected models", "[app][scene]") {
  SECTION("free_spin") {
    const scene::Scene s = read_bundled("free_spin");
    CHECK(s.name == "free_spin");
    CHECK(s.file == "scenes/free_spin.toml");
    CHECK(s.end_time == 100.0);
    CHECK(s.output_step == 0.1);
    const core::Model& m = *s.model;
    REQUIRE(m.num_bodies() == 1);
    CHECK(m.body(0).mass() == 1.0);
    CHECK(m.body(0).is_free());
    CHECK(m.body(0).I_Br_B() == diag(3.0, 4.0, 5.0));
    CHECK(m.body(0).description().initial.w_WB_B == Eigen::Vector3d(0.2, 0.3, 2.0));
    CHECK(m.body(0).description().initial.v_WBo == Eigen::Vector3d::Zero());
    CHECK(m.body(0).description().initial.theta_WB == rotation::identity_euler_parameters());
    REQUIRE(m.body(0).description().points.size() == 1);
    CHECK(m.body(0).description().points[0].name == "corner");
    CHECK(m.body(0).description().points[0].p_BoP_B == Eigen::Vector3d(1.0, 0.0, 0.0));
    CHECK(m.elements().empty());
    CHECK(m.discontinuities().empty());
    CHECK(initial_accelerations_finite(m));
  }
  SECTION("book_toss: sin² torque pulse on [0, 0.1)") {
    const scene::Scene s = read_bundled("book_toss");
    CHECK(s.end_time == 10.0);
    CHECK(s.output_step == 0.01);
    const core::Model& m = *s.model;
    REQUIRE(m.num_bodies() == 1);
    CHECK(m.body(0).name() == "book");
    CHECK(m.body(0).I_Br_B() == diag(1.0, 2.0, 2.8));
    CHECK(m.body(0).description().initial.w_WB_B == Eigen::Vector3d(0.0, 10.0, 0.0));
    CHECK(m.body(0).description().points.at(0).name == "corner");
    CHECK(m.elements().size() == 1);
    CHECK(m.discontinuities() == std::vector<double>{0.0, 0.1});
    // sin²(π·0.025/0.1) = 1/2 at a quarter of the pulse; nothing after it.
    CHECK(loads_at(m, 0.025).wrenches[0].tau_Br_W.isApprox(Eigen::Vector3d(0.1, 0.0, 0.1), 1e-14));
    CHECK(loads_at(m, 0.1).wrenches[0].tau_Br_W == Eigen::Vector3d::Zero());
    CHECK(initial_accelerations_finite(m));
  }
  SECTION("book_toss_step: rectangular torque pulse on [0, 0.1)") {
    const scene::Scene s = read_bundled("book_toss_step");
    const core::Model& m = *s.model;
    CHECK(m.body(0).I_Br_B() == diag(1.0, 2.0, 2.8));
    CHECK(m.elements().size() == 1);
    CHECK(m.discontinuities() == std::vector<double>{0.0, 0.1});
    CHECK(loads_at(m, 0.025).wrenches[0].tau_Br_W == Eigen::Vector3d(0.2, 0.0, 0.2));
    CHECK(loads_at(m, 0.0999).wrenches[0].tau_Br_W == Eigen::Vector3d(0.2, 0.0, 0.2));
    CHECK(loads_at(m, 0.1).wrenches[0].tau_Br_W == Eigen::Vector3d::Zero());
  }
  SECTION("coulomb_wall: two charges, attractor below the wall") {
    const scene::Scene s = read_bundled("coulomb_wall");
    CHECK(s.end_time == 100.0);
    const core::Model& m = *s.model;
    REQUIRE(m.num_bodies() == 1);
    CHECK(m.body(0).I_Br_B() == diag(0.4, 0.9, 1.1));
    const core::BodyInitialState& init = m.body(0).description().initial;
    CHECK(init.p_WBo == Eigen::Vector3d(0.0, 0.0, 1.0));
    CHECK(init.v_WBo == Eigen::Vector3d(0.8, 0.0, 0.0));
    CHECK(init.w_WB_B == Eigen::Vector3d(0.2, 0.3, 1.5));
    const auto& points = m.body(0).description().points;
    REQUIRE(points.size() == 2);
    CHECK(points[0].p_BoP_B == Eigen::Vector3d(0.5, 0.0, 0.0));
    CHECK(points[1].p_BoP_B == Eigen::Vector3d(-0.5, 0.0, 0.0));
    CHECK(m.elements().size() == 1);
    // V = Σ c (−α/|r − M| + β/z) with both charges at |r − M| = √(0.5² + 2²), z = 1.
    const double per_unit = -4.0 / std::sqrt(0.25 + 4.0) + 0.3 / 1.0;
    core::Workspace ws = m.make_workspace();
    CHECK(m.potential_energy({}, m.initial_state(), ws) ==
          Approx((1.0 + 0.6) * per_unit).epsilon(1e-14));
    CHECK(initial_accelerations_finite(m));
  }
  SECTION("heavy_top: inertia shifted to the pivot, gravity") {
    const scene::Scene s = read_bundled("heavy_top");
    CHECK(s.end_time == 2.0);
    CHECK(s.output_step == 0.01);
    const core::Model& m = *s.model;
    REQUIRE(m.num_bodies() == 1);
    const core::Body& top = m.body(0);
    CHECK(top.motion() == core::MotionKind::kPivot);
    CHECK(top.mass() == 15.0);
    // Parallel axis: I_pivot = I_C + m (|d|² I − d dᵀ), d = (0, 1, 0).
    CHECK(top.I_Br_B().isApprox(diag(0.234375 + 15.0, 0.46875, 0.234375 + 15.0), 1e-15));
    CHECK(top.description().initial.w_WB_B == Eigen::Vector3d(0.0, 150.0, -4.61538));
    CHECK(top.description().points.at(0).name == "tip");
    CHECK(top.description().points.at(0).p_BoP_B == Eigen::Vector3d(0.0, 1.0, 0.0));
    REQUIRE(m.elements().size() == 1);  // gravity
    // Torque of m g at (0, 1, 0) about the pivot: (0, 1, 0) × (0, 0, −15·9.81).
    CHECK(
        loads_at(m, 0.0).wrenches[0].tau_Br_W.isApprox(Eigen::Vector3d(-15.0 * 9.81, 0, 0), 1e-15));
    CHECK(m.discontinuities().empty());
    CHECK(initial_accelerations_finite(m));
  }
  SECTION("pendulum: released horizontal") {
    const scene::Scene s = read_bundled("pendulum");
    const core::Model& m = *s.model;
    REQUIRE(m.num_bodies() == 1);
    const core::Body& p = m.body(0);
    CHECK(p.motion() == core::MotionKind::kPivot);
    CHECK(p.I_Br_B().isApprox(diag(1e-3, 1e-3 + 1.0, 1e-3 + 1.0), 1e-15));
    CHECK(p.description().points.at(0).name == "bob");
    CHECK(p.description().initial.w_WB_B == Eigen::Vector3d::Zero());
    // Horizontal: the centre of mass starts at world (1, 0, 0), level with the pivot.
    CHECK(m.p_WP(0, m.initial_state()[0], p.description().p_BoBcm_B) ==
          Eigen::Vector3d(1.0, 0.0, 0.0));
    CHECK(loads_at(m, 0.0).wrenches[0].tau_Br_W.isApprox(Eigen::Vector3d(0, 9.81, 0), 1e-15));
    CHECK(initial_accelerations_finite(m));
  }
}

TEST_CASE("the minimal test scene is valid", "[app][scene]") {
  const scene::Scene s = scene::parse_scene(kMinimalScene + kBody, "ok.toml");
  CHECK(s.name == "t");
  CHECK(s.file == "ok.toml");
  CHECK(s.model->num_bodies() == 1);
}

TEST_CASE("sub-tables and arrays of tables may use headers", "[app][scene]") {
  const scene::Scene s =
      scene::parse_scene(kMinimalScene + kBody +
                             "[[body.points]]\nname = \"p\"\nat = [1, 0, 0]\n"
                             "[[load]]\nkind = \"force\"\nbody = \"b\"\nvalue = [1, 0, 0]\n"
                             "at = [0, 1, 0]\nframe = \"body\"\n"
                             "[load.profile]\nshape = \"rectangular_pulse\"\nstart = 1\n"
                             "duration = 2\n",
                         "ok.toml");
  REQUIRE(s.model->body(0).description().points.size() == 1);
  CHECK(s.model->body(0).description().points[0].p_BoP_B == Eigen::Vector3d(1, 0, 0));
  CHECK(s.model->discontinuities() == std::vector<double>{1.0, 3.0});
  // A force (1, 0, 0) at body point (0, 1, 0): torque (0, 1, 0) × (1, 0, 0) = (0, 0, −1).
  CHECK(loads_at(*s.model, 2.0).wrenches[0].tau_Br_W == Eigen::Vector3d(0, 0, -1));
  require_scene_error(kMinimalScene + kBody + "[[body.points]]\nname = \"p\"\n", 9,
                      "body[1].points[1].at", "required key is missing");
}

TEST_CASE("brackets in strings and comments are not nesting", "[app][scene]") {
  // The nesting guard (scene_toml.cpp) lexes strings and comments: 40 brackets there are text.
  const std::string brackets(40, '[');
  const scene::Scene s = scene::parse_scene(
      "# " + brackets + "\n[scene]\nname = \"t\"\ndescription = \"\"\"" + brackets +
          "\n{'\\\"\"\"\"\nend_time = 1.0\noutput_step = 0.1\n" + kBody,
      "ok.toml");
  CHECK(s.description == brackets + "\n{'\"");
}

TEST_CASE("every bad input is an InputError naming file, line and key", "[app][scene]") {
  SECTION("unknown key, at every level") {
    require_scene_error("colour = 1\n" + kMinimalScene + kBody, 1, "colour", "unknown key");
    require_scene_error(kMinimalScene + "nmae = \"x\"\n" + kBody, 5, "scene.nmae",
                        "expected one of: name,");
    require_scene_error(kMinimalScene + kBody + "mas = 1.0\n", 9, "body[1].mas", "unknown key");
    require_scene_error(
        kMinimalScene + kBody + "points = [{ name = \"p\", at = [0, 0, 0], size = 1 }]\n", 9,
        "body[1].points[1].size", "unknown key");
    require_scene_error(kMinimalScene + kBody +
                            "[[load]]\nkind = \"torque\"\nbody = \"b\"\nvalue = [0, 0, 1]\n"
                            "profile = { shape = \"sin2_pulse\", duration = 1, stat = 0 }\n",
                        13, "load[1].profile.stat", "unknown key");
    require_scene_error(kMinimalScene + kBody +
                            "[[potential]]\nkind = \"point_charge\"\nalpha = 1\nbeta = 1\n"
                            "attractor = [0, 0, -1]\n"
                            "charges = [{ body = \"b\", at = [0, 0, 1], wieght = 1 }]\n",
                        14, "potential[1].charges[1].wieght", "unknown key");
    // Contacts and joints are read (tests/scene/contact_scene_test.cpp); their kinds are checked.
    require_scene_error(kMinimalScene + kBody + "[[contact]]\nkind = \"sphere_plane\"\n", 10,
                        "contact[1].kind", "sphere-plane");
    require_scene_error(kMinimalScene + kBody + "modal = { file = \"m.txt\" }\n", 9,
                        "body[1].modal",
                        "expected the path of a modal-data file (TOML), got { file");
  }
  SECTION("missing key") {
    require_scene_error("[scene]\nname = \"t\"\noutput_step = 0.1\n" + kBody, 1, "scene.end_time",
                        "required key is missing");
    require_scene_error(kMinimalScene + "[[body]]\nname = \"b\"\ninertia = [1, 1, 1]\n", 5,
                        "body[1].mass", "positive mass in kg");
    require_scene_error(kMinimalScene + kBody + "[[load]]\nkind = \"force\"\nbody = \"b\"\n", 9,
                        "load[1].value", "force [x, y, z] in N");
    require_scene_error(kBody, 1, "scene", "[scene] table");
    require_scene_error(kMinimalScene, 1, "body", "at least one [[body]]");
    require_scene_error(kMinimalScene + kBody + "points = [{ at = [1, 0, 0] }]\n", 9,
                        "body[1].points[1].name", "required key is missing");
  }
  SECTION("wrong type") {
    require_scene_error(
        kMinimalScene + "[[body]]\nname = \"b\"\nmass = \"1.0\"\ninertia = [1, 1, 1]\n", 7,
        "body[1].mass", "got \"1.0\" (a string)");
    require_scene_error(kMinimalScene + kBody + "angular_velocity = [1.0, 2.0]\n", 9,
                        "body[1].angular_velocity", "got [1.0, 2.0] (an array of 2 elements)");
    require_scene_error(kMinimalScene + kBody + "position = [0, true, 0]\n", 9, "body[1].position",
                        "got true (a boolean)");
    require_scene_error(kMinimalScene + "[body]\nname = \"b\"\n", 5, "body", "write [[body]]");
    require_scene_error(kMinimalScene + kBody + "points = { name = \"p\" }\n", 9, "body[1].points",
                        "got a single table");
    require_scene_error("[scene]\nname = 3\nend_time = 1.0\noutput_step = 0.1\n" + kBody, 2,
                        "scene.name", "got 3 (an integer)");
    // Names are restricted to what CSV headers and command lines can carry.
    require_scene_error(
        kMinimalScene + "[[body]]\nname = \"my book\"\nmass = 1\ninertia = [1, 1, 1]\n", 6,
        "body[1].name", "letters, digits");
    // Integers are accepted where floats are expected...
    const scene::Scene s = scene::parse_scene(
        kMinimalScene + "[[body]]\nname = \"b\"\nmass = 2\ninertia = [1, 2, 2]\n", "ok.toml");
    CHECK(s.model->body(0).mass() == 2.0);
    // ... unless beyond ±2⁵³ (toml11 would clamp them silently).
    require_scene_error(kMinimalScene + kBody + "velocity = [0, 99999999999999999999, 0]\n", 9,
                        "body[1].velocity", "beyond ±2^53");
  }
  SECTION("non-finite number") {
    require_scene_error(kMinimalScene + "[[body]]\nname = \"b\"\nmass = nan\ninertia = [1, 1, 1]\n",
                        7, "body[1].mass", "got nan (infinite and NaN values are not allowed)");
    require_scene_error(kMinimalScene + kBody + "velocity = [0, -inf, 0]\n", 9, "body[1].velocity",
                        "-inf");
    require_scene_error("[scene]\nname = \"t\"\nend_time = inf\noutput_step = 0.1\n" + kBody, 3,
                        "scene.end_time", "not allowed");
    require_scene_error(kMinimalScene + kBody + "center_of_mass = [1e400, 0, 0]\n", 9,
                        "body[1].center_of_mass", "beyond the range of a double");
    // An element on its own line of a multi-line table is reported at its line.
    require_scene_error(kMinimalScene +
                            "[[body]]\nname = \"b\"\nmass = 1\ninertia = [\n  [1, 0, 0],\n"
                            "  [0, nan, 0],\n  [0, 0, 1],\n]\n",
                        10, "body[1].inertia", "nan");
  }
  SECTION("mass <= 0") {
    require_scene_error(kMinimalScene + "[[body]]\nname = \"b\"\nmass = 0\ninertia = [1, 1, 1]\n",
                        7, "body[1].mass", "expected a positive mass in kg, got 0");
    require_scene_error(
        kMinimalScene + "[[body]]\nname = \"b\"\nmass = -1.5\ninertia = [1, 1, 1]\n", 7,
        "body[1].mass", "got -1.5");
  }
  SECTION("inertia not symmetric positive definite or violating the triangle inequality") {
    const std::string head = kMinimalScene + "[[body]]\nname = \"b\"\nmass = 1\n";
    require_scene_error(head + "inertia = [1, -1, 1]\n", 8, "body[1].inertia",
                        "not positive definite");
    require_scene_error(head + "inertia = [0, 0, 0]\n", 8, "body[1].inertia",
                        "not positive definite");
    require_scene_error(head + "inertia = [[2, 0.1, 0], [0, 2, 0], [0, 0, 2]]\n", 8,
                        "body[1].inertia", "not symmetric");
    require_scene_error(head + "inertia = [1, 1, 3]\n", 8, "body[1].inertia",
                        "triangle inequality");
    require_scene_error(head + "inertia = [[1, 0], [0, 1], [0, 0]]\n", 8, "body[1].inertia",
                        "row 1 is [1, 0]");
    require_scene_error(head + "inertia = [1, [0, 1, 0], 1]\n", 8, "body[1].inertia", "row 1 is 1");
    // A full symmetric table is accepted; a flat disk J3 = J1 + J2 too.
    const scene::Scene full =
        scene::parse_scene(head + "inertia = [[2, 0.5, 0], [0.5, 3, 0], [0, 0, 4]]\n", "ok.toml");
    CHECK(full.model->body(0).I_Br_B()(0, 1) == 0.5);
    CHECK_NOTHROW(scene::parse_scene(head + "inertia = [1, 1, 2]\n", "ok.toml"));
  }
  SECTION("inertia extremes whose derived data overflow") {
    const std::string head = kMinimalScene + "[[body]]\nname = \"b\"\n";
    require_scene_error(head + "mass = 1\ninertia = [1e-310, 1e-310, 1e-310]\n", 8,
                        "body[1].inertia", "not finite");
    // m d^2 = 1e320 about the pivot: the mass brings 300 of its orders of magnitude, the
    // distance 20; with the mass of a top and a centre of mass 1e300 m away, the distance.
    require_scene_error(head +
                            "mass = 1e300\ninertia = [1, 1, 1]\ncenter_of_mass = [1e10, 0, 0]\n"
                            "motion = \"pivot\"\npivot = [0, 0, 0]\n",
                        7, "body[1].mass", "the inertia about the pivot, m d^2 with m = 1e+300 kg");
    require_scene_error(head +
                            "mass = 15\ninertia = [1, 1, 1]\ncenter_of_mass = [0, 1e300, 0]\n"
                            "motion = \"pivot\"\npivot = [0, 0, 0]\n",
                        9, "body[1].center_of_mass",
                        "d = 1e+300 m (the centre of mass from the pivot)");
  }
  SECTION("finite input whose model overflows") {
    require_scene_error(
        kMinimalScene + "[[body]]\nname = \"b\"\nmass = 1e-320\ninertia = [1, 1, 1]\n", 7,
        "body[1].mass", "too small");
    require_scene_error(kMinimalScene + kBody + "angular_velocity = [1e200, 0, 1e200]\n", 5,
                        "body[1]", "not finite");
  }
  SECTION("orientation not unit") {
    require_scene_error(kMinimalScene + kBody + "orientation = [1, 0, 0, 0.1]\n", 9,
                        "body[1].orientation", "got norm 1.004987562");
    require_scene_error(kMinimalScene + kBody + "orientation = [0, 0, 0, 0]\n", 9,
                        "body[1].orientation", "norm 0");
    require_scene_error(kMinimalScene + kBody + "orientation = [1, 0, 0]\n", 9,
                        "body[1].orientation", "[e0, e1, e2, e3]");
    // Within 1e-6 of unit norm: renormalized.
    const scene::Scene s = scene::parse_scene(
        kMinimalScene + kBody + "orientation = [0.7071068, 0.7071068, 0, 0]\n", "ok.toml");
    CHECK(s.model->body(0).description().initial.theta_WB.norm() == Approx(1.0).epsilon(1e-15));
  }
  SECTION("body referenced by a load or a charge does not exist") {
    require_scene_error(
        kMinimalScene + kBody + "[[load]]\nkind = \"torque\"\nbody = \"bok\"\nvalue = [0, 0, 1]\n",
        11, "load[1].body", "no [[body]] named \"bok\"; expected one of \"b\"");
    require_scene_error(kMinimalScene + kBody +
                            "[[potential]]\nkind = \"point_charge\"\nalpha = 1\nbeta = 1\n"
                            "attractor = [0, 0, -1]\n"
                            "charges = [{ body = \"c\", at = [0, 0, 1] }]\n",
                        14, "potential[1].charges[1].body", "no [[body]] named \"c\"");
  }
  SECTION("end_time <= 0") {
    require_scene_error("[scene]\nname = \"t\"\nend_time = 0\noutput_step = 0.1\n" + kBody, 3,
                        "scene.end_time", "expected a positive end time in s, got 0");
    require_scene_error("[scene]\nname = \"t\"\nend_time = -2.0\noutput_step = 0.1\n" + kBody, 3,
                        "scene.end_time", "got -2.0");
  }
  SECTION("output_step <= 0 or larger than end_time") {
    require_scene_error("[scene]\nname = \"t\"\nend_time = 1\noutput_step = 0.0\n" + kBody, 4,
                        "scene.output_step", "expected a positive output step in s, got 0.0");
    require_scene_error("[scene]\nname = \"t\"\nend_time = 1\noutput_step = 2\n" + kBody, 4,
                        "scene.output_step", "no larger than end_time = 1 s");
    require_scene_error("[scene]\nname = \"t\"\nend_time = 1e9\noutput_step = 1\n" + kBody, 4,
                        "scene.output_step", "at most 1e7 output intervals");
  }
  SECTION("duplicate body names") {
    require_scene_error(kMinimalScene + kBody + kBody, 10, "body[2].name",
                        "duplicate body name \"b\" (first defined at line 6)");
  }
  SECTION("duplicate point names in a body") {
    require_scene_error(kMinimalScene + kBody +
                            "points = [\n  { name = \"p\", at = [1, 0, 0] },\n"
                            "  { name = \"p\", at = [0, 1, 0] },\n]\n",
                        11, "body[1].points[2].name", "duplicate point name \"p\"");
  }
  SECTION("negative pulse duration") {
    const std::string load = kMinimalScene + kBody +
                             "[[load]]\nkind = \"force\"\nbody = \"b\"\nvalue = [1, 0, 0]\n"
                             "at = [0, 1, 0]\n";
    require_scene_error(load + "profile = { shape = \"rectangular_pulse\", duration = -0.1 }\n", 14,
                        "load[1].profile.duration",
                        "expected a positive pulse duration in s, got -0.1");
    require_scene_error(load + "profile = { shape = \"sin2_pulse\", start = 1 }\n", 14,
                        "load[1].profile.duration", "required key is missing");
    require_scene_error(load + "profile = { shape = \"constant\", duration = 1 }\n", 14,
                        "load[1].profile.duration", "applies only to pulses");
  }
  SECTION("unknown enum values") {
    require_scene_error(
        kMinimalScene + kBody + "motion = \"fixed\"\n", 9, "body[1].motion",
        "expected one of \"free\", \"pivot\", \"prescribed\", got \"fixed\" (a string)");
    require_scene_error(kMinimalScene + kBody + "motion = \"prescribed\"\n", 9, "body[1].motion",
                        "applies only to flexible bodies");
    const std::string load = kMinimalScene + kBody + "[[load]]\nbody = \"b\"\nvalue = [1, 0, 0]\n";
    require_scene_error(load + "kind = \"moment\"\n", 12, "load[1].kind",
                        "expected one of \"torque\", \"force\"");
    require_scene_error(load + "kind = \"torque\"\nframe = \"global\"\n", 13, "load[1].frame",
                        "expected one of \"world\", \"body\"");
    require_scene_error(load + "kind = \"torque\"\nprofile = { shape = \"step\" }\n", 13,
                        "load[1].profile.shape", "\"sin2_pulse\", \"rectangular_pulse\"");
    require_scene_error(kMinimalScene + kBody + "[[potential]]\nkind = \"spring\"\n", 10,
                        "potential[1].kind", "expected one of \"point_charge\"");
  }
  SECTION("TOML syntax errors carry their line") {
    try {
      (void)scene::parse_scene(kMinimalScene + kBody + "velocity = [0, 0,\n\n]]\n", "bad.toml");
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.line() == 11);
      CHECK(e.key().empty());
      CHECK_THAT(e.what(), Contains("bad.toml:11: TOML syntax error"));
    }
    try {
      (void)scene::parse_scene(kMinimalScene + "name = \"again\"\n" + kBody, "bad.toml");
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.line() == 5);
      CHECK_THAT(e.what(), Contains("bad.toml:5: TOML syntax error"));
    }
    try {
      (void)scene::parse_scene(kMinimalScene + "a = " + std::string(100000, '['), "bad.toml");
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.line() == 5);
      CHECK_THAT(e.what(), Contains("nested deeper than 32 levels"));
    }
  }
  SECTION("pivot, velocity and point of application where they do not apply") {
    require_scene_error(kMinimalScene + kBody + "motion = \"pivot\"\n", 5, "body[1].pivot",
                        "required key is missing");
    require_scene_error(kMinimalScene + kBody + "pivot = [0, 0, 0]\n", 9, "body[1].pivot",
                        "applies only to motion = \"pivot\"");
    require_scene_error(
        kMinimalScene + kBody + "motion = \"pivot\"\npivot = [1, 0, 0]\nvelocity = [0, 1, 0]\n", 11,
        "body[1].velocity", "with motion = \"pivot\"");
    CHECK_NOTHROW(scene::parse_scene(
        kMinimalScene + kBody + "motion = \"pivot\"\npivot = [1, 0, 0]\nvelocity = [0, 0, 0]\n",
        "ok"));
    require_scene_error(
        kMinimalScene + kBody +
            "[[load]]\nkind = \"torque\"\nbody = \"b\"\nvalue = [1, 0, 0]\nat = [1, 0, 0]\n",
        13, "load[1].at", "applies only to forces");
  }
  SECTION("charges must start above the wall") {
    require_scene_error(kMinimalScene + kBody +
                            "[[potential]]\nkind = \"point_charge\"\nalpha = 1\nbeta = 1\n"
                            "attractor = [0, 0, -1]\n"
                            "charges = [{ body = \"b\", at = [0, 0, -0.5] }]\n",
                        14, "potential[1].charges[1].at", "starts at z = -0.5");
    require_scene_error(kMinimalScene + kBody +
                            "[[potential]]\nkind = \"point_charge\"\nalpha = 1\nbeta = 1\n"
                            "attractor = [0, 0, -1]\ncharges = []\n",
                        14, "potential[1].charges", "at least one charge");
  }
  SECTION("files that cannot be read") {
    try {
      (void)scene::read_scene("scenes/no_such_scene.toml");
      FAIL("accepted");
    } catch (const core::InputError& e) {
      CHECK(e.file() == "scenes/no_such_scene.toml");
      CHECK_THAT(e.what(), Contains("cannot open"));
    }
    CHECK_THROWS_AS(scene::read_scene("scenes"), core::InputError);
  }
}

}  // namespace flexref::app
