// [[contact]] and [[joint]] tables of scene files (scenes/README.md), the bundled contact
// scenes, and the dissipated-work columns of the trajectory CSV (docs/output.md).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>

#include "contact/bushing.hpp"
#include "contact/contact.hpp"
#include "core/error.hpp"
#include "core/step_limit.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/scene_error_checks.hpp"
#include "tests/support/temp_dir.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
namespace {

using testing::require_scene_error;

using Catch::Matchers::Contains;

// Lines 1-5 [scene], 6-10 body "a", 11-15 body "b"; additions start at line 16.
const std::string kHead =
    "[scene]\n"
    "name = \"t\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n"
    "gravity = [0, 0, -9.81]\n"
    "[[body]]\n"
    "name = \"a\"\n"
    "mass = 2.0\n"
    "inertia = [1.0, 1.0, 1.0]\n"
    "position = [0, 0, 1]\n"
    "[[body]]\n"
    "name = \"b\"\n"
    "mass = 1.0\n"
    "inertia = [0.5, 0.5, 0.5]\n"
    "position = [0, 0, 3]\n";
constexpr int kFirst = 16;  // line of the first added line

template <class T>
const T& element(const scene::Scene& scene, int index) {
  const auto* e =
      dynamic_cast<const T*>(scene.model->elements()[static_cast<std::size_t>(index)].get());
  REQUIRE(e != nullptr);
  return *e;
}

const std::string kSpherePlane =
    "[[contact]]\n"
    "kind = \"sphere-plane\"\n"
    "body = \"a\"\n"
    "center = [0, 0, 0]\n"
    "radius = 0.5\n";

}  // namespace

TEST_CASE("a sphere-plane contact with defaults follows docs/contact.md", "[app][scene][contact]") {
  const scene::Scene s = scene::parse_scene(kHead + kSpherePlane, "t.toml");
  REQUIRE(s.model->elements().size() == 2);  // gravity, contact
  const auto& c = element<contact::ContactElement>(s, 1);
  REQUIRE(c.pairs().size() == 1);
  const contact::ContactPair& p = c.pairs()[0];
  CHECK(p.kind == contact::ContactPair::Kind::kSpherePlane);
  CHECK(p.body_b == 0);
  CHECK(p.radius_b == 0.5);
  CHECK(p.p_WQ.isZero(0.0));
  CHECK(p.n_W == Eigen::Vector3d::UnitZ());
  const contact::NormalLaw& law = c.normal_law();
  CHECK(law.kind() == contact::NormalLaw::Kind::kHuntCrossley);
  CHECK(law.stiffness() == 1e6);
  CHECK(law.exponent() == 1.5);
  CHECK(law.restitution() == 0.5);
  CHECK(law.reference_speed() == 1.0);
  CHECK(c.friction_law().mu == 0.0);
  CHECK(c.friction_law().v_reg == 1e-3);
  // m_eff = body mass / pairs = 2 kg.
  REQUIRE(core::penalty_modes(*s.model).size() == 1);
  CHECK(core::penalty_modes(*s.model)[0].label == "contact[1]");
  CHECK(core::penalty_modes(*s.model)[0].inertia == 2.0);
  CHECK(core::penalty_modes(*s.model)[0].frequency == Approx(c.frequency(2.0)).epsilon(1e-15));
  CHECK(core::penalty_modes(*s.model)[0].step_limit ==
        Approx(c.explicit_step_limit(2.0)).epsilon(1e-15));
  CHECK(s.model->dissipates());
  CHECK(s.model->switching_function_count() == 1);
}

TEST_CASE("every contact key is read", "[app][scene][contact]") {
  SECTION("sphere-plane, several centres, Hunt-Crossley, friction") {
    const scene::Scene s =
        scene::parse_scene(kHead +
                               "[[contact]]\n"
                               "kind = \"sphere-plane\"\n"
                               "body = \"b\"\n"
                               "centers = [[0.1, 0, 0], [-0.1, 0, 0], [0, 0.1, 0]]\n"
                               "radius = 0.01\n"
                               "plane_point = [0, 0, -1]\n"
                               "plane_normal = [0, 0.6, 0.8]\n"
                               "law = \"hunt-crossley\"\n"
                               "stiffness = 2e7\n"
                               "exponent = 1.2\n"
                               "restitution = 0.8\n"
                               "reference_speed = 3\n"
                               "friction = 0.4\n"
                               "regularization_speed = 1e-2\n"
                               "effective_mass = 0.25\n",
                           "t.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    REQUIRE(c.pairs().size() == 3);
    CHECK(c.pairs()[1].body_b == 1);
    CHECK(c.pairs()[1].p_BoCb_B == Eigen::Vector3d(-0.1, 0, 0));
    CHECK(c.pairs()[2].radius_b == 0.01);
    CHECK(c.pairs()[0].p_WQ == Eigen::Vector3d(0, 0, -1));
    // (0, 3, 4) normalized: a square root and three divisions, ≤ 2 ε = 4.4e-16 each.
    CHECK(c.pairs()[0].n_W.isApprox(Eigen::Vector3d(0, 0.6, 0.8), 1e-15));
    CHECK(c.normal_law().stiffness() == 2e7);
    CHECK(c.normal_law().exponent() == 1.2);
    CHECK(c.normal_law().restitution() == 0.8);
    CHECK(c.normal_law().reference_speed() == 3.0);
    CHECK(c.friction_law().mu == 0.4);
    CHECK(c.friction_law().v_reg == 1e-2);
    CHECK(core::penalty_modes(*s.model)[0].inertia == 0.25);
  }
  SECTION("point-plane, linear law with damping; default m_eff = mass / pairs") {
    const scene::Scene s = scene::parse_scene(kHead +
                                                  "[[contact]]\n"
                                                  "kind = \"point-plane\"\n"
                                                  "body = \"a\"\n"
                                                  "points = [[0.1, 0.1, -0.1], [0.1, -0.1, -0.1], "
                                                  "[-0.1, 0.1, -0.1], [-0.1, -0.1, -0.1]]\n"
                                                  "law = \"linear\"\n"
                                                  "stiffness = 4e5\n"
                                                  "damping = 30\n",
                                              "t.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    REQUIRE(c.pairs().size() == 4);
    CHECK(c.pairs()[3].radius_b == 0.0);
    CHECK(c.pairs()[3].p_BoCb_B == Eigen::Vector3d(-0.1, -0.1, -0.1));
    CHECK(c.normal_law().kind() == contact::NormalLaw::Kind::kLinear);
    CHECK(c.normal_law().stiffness() == 4e5);
    CHECK(c.normal_law().damping() == 30.0);
    CHECK(core::penalty_modes(*s.model)[0].inertia == 0.5);
    // Tolerance: √(k/m) and 2/ω from the scene's numbers: a few roundings of O(1)-relative
    // operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
    CHECK(core::penalty_modes(*s.model)[0].frequency ==
          Approx(std::sqrt(4e5 / 0.5)).epsilon(1e-14));
    CHECK(core::penalty_modes(*s.model)[0].step_limit ==
          Approx(2.0 / std::sqrt(4e5 / 0.5)).epsilon(1e-14));
  }
  SECTION("point-plane, linear law from restitution with m_eff") {
    const scene::Scene s = scene::parse_scene(kHead +
                                                  "[[contact]]\n"
                                                  "kind = \"point-plane\"\n"
                                                  "body = \"a\"\n"
                                                  "point = [0, 0, -0.5]\n"
                                                  "law = \"linear\"\n"
                                                  "restitution = 0.5\n",
                                              "t.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    const contact::NormalLaw expected = contact::NormalLaw::linear_from_restitution(1e6, 0.5, 2.0);
    CHECK(c.normal_law().damping() == Approx(expected.damping()).epsilon(1e-15));
  }
  SECTION("sphere-sphere: m_eff is the reduced mass") {
    const scene::Scene s = scene::parse_scene(kHead +
                                                  "[[contact]]\n"
                                                  "kind = \"sphere-sphere\"\n"
                                                  "body = \"a\"\n"
                                                  "center = [0, 0, 0.1]\n"
                                                  "radius = 0.5\n"
                                                  "body_b = \"b\"\n"
                                                  "center_b = [0, 0, -0.1]\n"
                                                  "radius_b = 0.25\n",
                                              "t.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    const contact::ContactPair& p = c.pairs()[0];
    CHECK(p.kind == contact::ContactPair::Kind::kSphereSphere);
    CHECK(p.body_a == 0);
    CHECK(p.body_b == 1);
    CHECK(p.radius_a == 0.5);
    CHECK(p.radius_b == 0.25);
    CHECK(p.p_BoCa_B == Eigen::Vector3d(0, 0, 0.1));
    CHECK(p.p_BoCb_B == Eigen::Vector3d(0, 0, -0.1));
    // Tolerance: 1/(1/m_a + 1/m_b) from the scene's masses: a few roundings of O(1)-relative
    // operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
    CHECK(core::penalty_modes(*s.model)[0].inertia == Approx(2.0 / 3.0).epsilon(1e-14));
  }
  SECTION("a plane normal within 1e-6 of unit is renormalized") {
    const scene::Scene s =
        scene::parse_scene(kHead + kSpherePlane + "plane_normal = [0, 0, 1.0000005]\n", "t.toml");
    CHECK(element<contact::ContactElement>(s, 1).pairs()[0].n_W == Eigen::Vector3d::UnitZ());
  }
}

TEST_CASE("contact errors name file, line and key", "[app][scene][contact]") {
  const int l = kFirst;  // [[contact]] header
  SECTION("unknown key, kind, law") {
    require_scene_error(kHead + kSpherePlane + "radiu = 1\n", l + 5, "contact[1].radiu",
                        "unknown key");
    require_scene_error(kHead + "[[contact]]\nkind = \"box-plane\"\n", l + 1, "contact[1].kind",
                        "sphere-plane");
    require_scene_error(kHead + kSpherePlane + "law = \"hertz\"\n", l + 5, "contact[1].law",
                        "linear");
  }
  SECTION("missing and wrong keys") {
    require_scene_error(kHead + "[[contact]]\nbody = \"a\"\n", l, "contact[1].kind", "missing");
    require_scene_error(kHead + "[[contact]]\nkind = \"sphere-plane\"\nbody = \"c\"\n", l + 2,
                        "contact[1].body", "no [[body]] named \"c\"");
    require_scene_error(kHead + "[[contact]]\nkind = \"sphere-plane\"\nbody = \"a\"\nradius = 1\n",
                        l, "contact[1].center", "missing");
    require_scene_error(
        kHead + "[[contact]]\nkind = \"sphere-plane\"\nbody = \"a\"\ncenter = [0, 0, 0]\n", l,
        "contact[1].radius", "missing");
    require_scene_error(kHead + kSpherePlane + "centers = [[0, 0, 0]]\n", l + 5,
                        "contact[1].centers", "not both");
    require_scene_error(kHead +
                            "[[contact]]\nkind = \"sphere-plane\"\nbody = \"a\"\nradius = 1\n"
                            "centers = [[0, 0, 0], [1, 2]]\n",
                        l + 4, "contact[1].centers", "array of");
    require_scene_error(kHead +
                            "[[contact]]\nkind = \"sphere-plane\"\nbody = \"a\"\nradius = 1\n"
                            "centers = []\n",
                        l + 4, "contact[1].centers", "at least one");
    require_scene_error(kHead + "[[contact]]\nkind = \"point-plane\"\nbody = \"a\"\n", l,
                        "contact[1].point", "missing");
    require_scene_error(kHead +
                            "[[contact]]\nkind = \"point-plane\"\nbody = \"a\"\npoint = [0, 0, 0]\n"
                            "radius = 1\n",
                        l + 4, "contact[1].radius", "point-plane");
    require_scene_error(kHead + kSpherePlane + "body_b = \"b\"\n", l + 5, "contact[1].body_b",
                        "sphere-sphere");
    require_scene_error(
        kHead + "[[contact]]\nkind = \"sphere-sphere\"\nbody = \"a\"\nbody_b = \"a\"\n", l + 3,
        "contact[1].body_b", "two different bodies");
    require_scene_error(kHead +
                            "[[contact]]\nkind = \"sphere-sphere\"\nbody = \"a\"\nbody_b = \"b\"\n"
                            "center = [0, 0, 0]\nradius = 1\ncenter_b = [0, 0, 0]\nradius_b = 1\n"
                            "plane_normal = [0, 0, 1]\n",
                        l + 8, "contact[1].plane_normal", "sphere-plane");
  }
  SECTION("plane normal") {
    require_scene_error(kHead + kSpherePlane + "plane_normal = [0, 0, 2]\n", l + 5,
                        "contact[1].plane_normal", "norm 1 within 1e-6");
    require_scene_error(kHead + kSpherePlane + "plane_normal = [0, 0]\n", l + 5,
                        "contact[1].plane_normal", "plane");
  }
  SECTION("numbers out of range") {
    require_scene_error(
        kHead +
            "[[contact]]\nkind = \"sphere-plane\"\nbody = \"a\"\ncenter = [0, 0, 0]\n"
            "radius = -1\n",
        l + 4, "contact[1].radius", "radius >= 0");
    require_scene_error(kHead +
                            "[[contact]]\nkind = \"sphere-plane\"\nbody = \"a\"\n"
                            "center = [0, 0, 1e400]\nradius = 1\n",
                        l + 3, "contact[1].center", "center");
  }
  SECTION("law parameters") {
    require_scene_error(kHead + kSpherePlane + "stiffness = -1\n", l + 5, "contact[1].stiffness",
                        "positive stiffness");
    require_scene_error(kHead + kSpherePlane + "stiffness = inf\n", l + 5, "contact[1].stiffness",
                        "stiffness");
    require_scene_error(kHead + kSpherePlane + "exponent = 0.5\n", l + 5, "contact[1].exponent",
                        ">= 1");
    require_scene_error(kHead + kSpherePlane + "restitution = 1.5\n", l + 5,
                        "contact[1].restitution", "(0, 1]");
    require_scene_error(kHead + kSpherePlane + "restitution = 0\n", l + 5, "contact[1].restitution",
                        "(0, 1]");
    require_scene_error(kHead + kSpherePlane + "reference_speed = 0\n", l + 5,
                        "contact[1].reference_speed", "positive");
    require_scene_error(kHead + kSpherePlane + "damping = 3\n", l + 5, "contact[1].damping",
                        "law = \"linear\"");
    require_scene_error(kHead + kSpherePlane + "law = \"linear\"\nexponent = 2\n", l + 6,
                        "contact[1].exponent", "hunt-crossley");
    require_scene_error(kHead + kSpherePlane + "law = \"linear\"\ndamping = 1\nrestitution = 0.5\n",
                        l + 6, "contact[1].damping", "not both");
    require_scene_error(kHead + kSpherePlane + "law = \"linear\"\ndamping = -1\n", l + 6,
                        "contact[1].damping", ">= 0");
    require_scene_error(kHead + kSpherePlane + "friction = -0.1\n", l + 5, "contact[1].friction",
                        "friction");
    require_scene_error(kHead + kSpherePlane + "regularization_speed = 0\n", l + 5,
                        "contact[1].regularization_speed", "positive");
    require_scene_error(kHead + kSpherePlane + "effective_mass = 0\n", l + 5,
                        "contact[1].effective_mass", "positive");
    require_scene_error(kHead + kSpherePlane + "friction = \"high\"\n", l + 5,
                        "contact[1].friction", "a string");
  }
}

// --- [[joint]] -----------------------------------------------------------------------------

namespace {
const std::string kRevolute =
    "[[joint]]\n"
    "kind = \"revolute\"\n"
    "body_a = \"b\"\n"
    "point_a = [0, 0, -1]\n"
    "body_b = \"a\"\n"
    "point_b = [0, 0, 1]\n"
    "axis_a = [0, 1, 0]\n"
    "axis_b = [0, 1, 0]\n";
}  // namespace

TEST_CASE("every joint key is read", "[app][scene][joint]") {
  SECTION("revolute between two bodies, defaults") {
    const scene::Scene s = scene::parse_scene(kHead + kRevolute, "t.toml");
    const auto& j = element<contact::RevoluteBushing>(s, 1);
    CHECK(j.end_a().body == 1);
    CHECK(j.end_b().body == 0);
    CHECK(j.end_a().point == Eigen::Vector3d(0, 0, -1));
    CHECK(j.end_b().point == Eigen::Vector3d(0, 0, 1));
    CHECK(j.end_a().axis == Eigen::Vector3d::UnitY());
    CHECK(j.translational_stiffness() == 1e6);
    CHECK(j.translational_damping() == 0.0);
    CHECK(j.angular_stiffness() == 1e4);
    CHECK(j.angular_damping() == 0.0);
    REQUIRE(core::penalty_modes(*s.model).size() == 2);
    CHECK(core::penalty_modes(*s.model)[0].label == "joint[1] translational");
    CHECK(core::penalty_modes(*s.model)[1].label == "joint[1] angular");
    // Free bodies at their centres of mass... translational: arms of 1 m.
    // Along x: 1/m_a + 1/m_b + r²/J_a + r²/J_b = 0.5 + 1 + 1 + 2 = 4.5.
    // Tolerance: sums of 1/m and r²/J (all positive: no cancellation), their inverse, √ and 2/ω:
    // a few roundings of O(1)-relative operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor
    // ~10 over them.
    CHECK(core::penalty_modes(*s.model)[0].inertia == Approx(1.0 / 4.5).epsilon(1e-14));
    CHECK(core::penalty_modes(*s.model)[0].frequency ==
          Approx(std::sqrt(1e6 * 4.5)).epsilon(1e-14));
    CHECK(core::penalty_modes(*s.model)[0].step_limit ==
          Approx(2.0 / std::sqrt(1e6 * 4.5)).epsilon(1e-14));
    // Angular, about x or z (perpendicular to the hinge): 1/J_a + 1/J_b = 3.
    CHECK(core::penalty_modes(*s.model)[1].inertia == Approx(1.0 / 3.0).epsilon(1e-14));
    CHECK(core::penalty_modes(*s.model)[1].frequency ==
          Approx(std::sqrt(1e4 * 3.0)).epsilon(1e-14));
  }
  SECTION("every key; damping lowers the step limit") {
    const scene::Scene s =
        scene::parse_scene(kHead + kRevolute +
                               "stiffness = 1e5\ndamping = 30\nangular_stiffness = 1e3\n"
                               "angular_damping = 2\n",
                           "t.toml");
    const auto& j = element<contact::RevoluteBushing>(s, 1);
    CHECK(j.translational_stiffness() == 1e5);
    CHECK(j.translational_damping() == 30.0);
    CHECK(j.angular_stiffness() == 1e3);
    CHECK(j.angular_damping() == 2.0);
    CHECK(core::penalty_modes(*s.model)[0].step_limit ==
          Approx(contact::bushing_stable_step(1e5, 30.0, 1.0 / 4.5)).epsilon(1e-14));
    CHECK(core::penalty_modes(*s.model)[0].step_limit < 2.0 / std::sqrt(1e5 * 4.5));
  }
  SECTION("a named bushing: its modes and description name it and its bodies") {
    const scene::Scene s = scene::parse_scene(kHead + kRevolute + "name = \"hinge\"\n", "t.toml");
    REQUIRE(core::penalty_modes(*s.model).size() == 2);
    CHECK(core::penalty_modes(*s.model)[0].label == "joint 'hinge' translational");
    CHECK(core::penalty_modes(*s.model)[1].label == "joint 'hinge' angular");
    CHECK(core::penalty_modes(*s.model)[1].element == 1);  // after the gravity element
    const auto& j = element<contact::RevoluteBushing>(s, 1);
    CHECK(j.label() == "joint 'hinge'");
    CHECK(j.describe_with_names(s.model->bodies())
              .starts_with(
                  "revolute bushing: body 'b' point (0, 0, -1) to body 'a' point (0, 0, 1)"));
    CHECK(j.describe().starts_with("revolute bushing: body[2] point (0, 0, -1) to body[1]"));
  }
  SECTION("spherical to the ground") {
    const scene::Scene s =
        scene::parse_scene(kHead +
                               "[[joint]]\nkind = \"spherical\"\nbody_a = \"a\"\n"
                               "point_a = [1, 0, 0]\nbody_b = \"ground\"\n"
                               "point_b = [1, 0, 1]\nstiffness = 1e4\n",
                           "t.toml");
    const auto& j = element<contact::SphericalBushing>(s, 1);
    CHECK(j.end_b().body == contact::kGround);
    CHECK(j.end_b().point == Eigen::Vector3d(1, 0, 1));
    CHECK(j.translational_stiffness() == 1e4);
    REQUIRE(core::penalty_modes(*s.model).size() == 1);
    CHECK(core::penalty_modes(*s.model)[0].label == "joint[1]");
    // Along y or z at arm 1 m along x: 1/2 + 1/1 = 1.5.
    // Tolerance: a sum of 1/m and r²/J and its inverse: a few roundings of O(1)-relative
    // operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
    CHECK(core::penalty_modes(*s.model)[0].inertia == Approx(1.0 / 1.5).epsilon(1e-14));
  }
}

TEST_CASE("joint errors name file, line and key", "[app][scene][joint]") {
  const int l = kFirst;
  require_scene_error(kHead + kRevolute + "axis = [0, 0, 1]\n", l + 8, "joint[1].axis",
                      "unknown key");
  require_scene_error(kHead + "[[joint]]\nkind = \"prismatic\"\n", l + 1, "joint[1].kind",
                      "revolute");
  // The ground as the first end: refused with what to do (it said "no [[body]] named ground").
  require_scene_error(kHead +
                          "[[joint]]\nkind = \"spherical\"\nbody_a = \"ground\"\n"
                          "body_b = \"a\"\n",
                      l + 2, "joint[1].body_a",
                      "the first end of a joint must be a body (its reactions are reported on "
                      "it); the ground can only be the second end: swap the ends, body_a = "
                      "\"a\" and body_b = \"ground\", exchanging point_a and point_b");
  require_scene_error(kHead + kRevolute + "[[joint]]\nname = \"j\"\n" +
                          kRevolute.substr(std::string("[[joint]]\n").size()) +
                          "[[joint]]\nname = \"j\"\n" +
                          kRevolute.substr(std::string("[[joint]]\n").size()),
                      l + 18, "joint[3].name", "duplicate joint name \"j\"");
  require_scene_error(kHead + "[[joint]]\nkind = \"spherical\"\nbody_a = \"a\"\nbody_b = \"a\"\n",
                      l + 3, "joint[1].body_b", "two different bodies");
  require_scene_error(
      kHead + "[[joint]]\nkind = \"spherical\"\nbody_a = \"a\"\nbody_b = \"ground\"\n", l,
      "joint[1].point_a", "missing");
  require_scene_error(kHead +
                          "[[joint]]\nkind = \"spherical\"\nbody_a = \"a\"\nbody_b = \"b\"\n"
                          "point_a = [0, 0, 0]\npoint_b = [0, 0, 0]\naxis_a = [0, 0, 1]\n",
                      l + 6, "joint[1].axis_a", "revolute");
  require_scene_error(kHead +
                          "[[joint]]\nkind = \"revolute\"\nbody_a = \"a\"\nbody_b = \"b\"\n"
                          "point_a = [0, 0, 0]\npoint_b = [0, 0, 0]\naxis_a = [0, 0, 1]\n",
                      l, "joint[1].axis_b", "missing");
  require_scene_error(kHead + kRevolute + "stiffness = -1\n", l + 8, "joint[1].stiffness",
                      "positive");
  require_scene_error(kHead + kRevolute + "damping = nan\n", l + 8, "joint[1].damping", "damping");
  require_scene_error(kHead + kRevolute + "angular_stiffness = -1\n", l + 8,
                      "joint[1].angular_stiffness", ">= 0");
  require_scene_error(kHead + kRevolute + "angular_damping = -1\n", l + 8,
                      "joint[1].angular_damping", ">= 0");
  require_scene_error(kHead +
                          "[[joint]]\nkind = \"revolute\"\nbody_a = \"a\"\nbody_b = \"b\"\n"
                          "point_a = [0, 0, 0]\npoint_b = [0, 0, 0]\naxis_a = [0, 0, 0.5]\n"
                          "axis_b = [0, 0, 1]\n",
                      l + 6, "joint[1].axis_a", "norm 1 within 1e-6");
}

TEST_CASE("bundled contact scenes read into the expected elements", "[app][scene][contact]") {
  SECTION("bouncing_ball") {
    const scene::Scene s = scene::read_scene("scenes/bouncing_ball.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    CHECK(c.pairs().size() == 1);
    CHECK(c.pairs()[0].radius_b == 0.1);
    CHECK(c.normal_law().kind() == contact::NormalLaw::Kind::kHuntCrossley);
    CHECK(c.normal_law().restitution() == 0.5);
    // √(2 g h), h = 0.9 m: the same three roundings in any order, ≤ 3 ε = 6.7e-16.
    CHECK(c.normal_law().reference_speed() == Approx(std::sqrt(2 * 9.81 * 0.9)).epsilon(1e-15));
    CHECK(s.model->body(0).mass() == 1.0);
    CHECK(s.model->initial_state()[0].p_WBr.z() == 1.0);
  }
  SECTION("sliding_block") {
    const scene::Scene s = scene::read_scene("scenes/sliding_block.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    CHECK(c.pairs().size() == 4);
    CHECK(c.normal_law().kind() == contact::NormalLaw::Kind::kLinear);
    CHECK(c.friction_law().mu == 0.5);
    CHECK(core::penalty_modes(*s.model)[0].inertia == 0.25);
  }
  SECTION("top_on_plane") {
    const scene::Scene s = scene::read_scene("scenes/top_on_plane.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    CHECK(c.pairs()[0].radius_b == 0.005);
    CHECK(c.pairs()[0].p_BoCb_B == Eigen::Vector3d(0, 0, -0.04));
    CHECK(c.friction_law().mu == 0.3);
  }
  SECTION("tippe_top") {
    const scene::Scene s = scene::read_scene("scenes/tippe_top.toml");
    REQUIRE(s.model->elements().size() == 3);
    const auto& sphere = element<contact::ContactElement>(s, 1);
    const auto& stem = element<contact::ContactElement>(s, 2);
    CHECK(sphere.pairs()[0].radius_b == 0.015);
    CHECK(stem.pairs()[0].radius_b == 0.005);
    // Tolerance: the distance of two centres written with ≤ 3 digits, O(0.01) apart on a body of
    // O(0.03) m: the difference's absolute error ≤ 2^-53 × 0.03 ≈ 3e-18, 2e-16 relative to 0.016;
    // 1e-13 leaves a wide factor.
    CHECK((stem.pairs()[0].p_BoCb_B - sphere.pairs()[0].p_BoCb_B).norm() ==
          Approx(0.016).epsilon(1e-13));
    CHECK(sphere.friction_law().mu == 0.3);
    CHECK(stem.friction_law().mu == 0.3);
    CHECK(s.model->body(0).mass() == 0.006);
  }
  SECTION("pendulum_on_sliding_support") {
    const scene::Scene s = scene::read_scene("scenes/pendulum_on_sliding_support.toml");
    const auto& c = element<contact::ContactElement>(s, 1);
    CHECK(c.pairs().size() == 4);
    CHECK(c.friction_law().mu == 0.2);
    const auto& j = element<contact::RevoluteBushing>(s, 2);
    CHECK(j.end_a().axis == Eigen::Vector3d::UnitY());
    CHECK(j.end_b().axis == Eigen::Vector3d::UnitY());
    // The hinge ends coincide at the start (the rod turned 60 degrees about y).
    const auto world = [&](int body, const Eigen::Vector3d& p) {
      const core::BodyInitialState& init = s.model->body(body).description().initial;
      return Eigen::Vector3d(init.p_WBo + rotation::rotation_matrix(init.theta_WB) * p);
    };
    CHECK((world(j.end_a().body, j.end_a().point) - world(j.end_b().body, j.end_b().point)).norm() <
          1e-12);
  }
  SECTION("double_pendulum_impacts") {
    const scene::Scene s = scene::read_scene("scenes/double_pendulum_impacts.toml");
    CHECK(s.model->body(0).motion() == core::MotionKind::kPivot);
    // Contacts come before joints in the model (gravity, loads, potentials, contacts, joints).
    const auto& j = element<contact::RevoluteBushing>(s, 2);
    CHECK(j.end_a().body == 1);
    CHECK(j.end_b().body == 0);
    const auto& c = element<contact::ContactElement>(s, 1);
    CHECK(c.pairs()[0].n_W == Eigen::Vector3d(-1, 0, 0));
    CHECK(c.pairs()[0].p_WQ == Eigen::Vector3d(0.8, 0, 0));
    CHECK(c.pairs()[0].radius_b == 0.05);
  }
}

TEST_CASE("the CSV of a dissipating model has dissipated work and the energy balance",
          "[app][csv][contact]") {
  const scene::Scene s = scene::parse_scene(kHead + kSpherePlane, "t.toml");
  const core::Model& model = *s.model;
  core::Trajectory trajectory;
  trajectory.times = {0.0, 0.5, 1.0};
  trajectory.states = {model.initial_state(), model.initial_state(), model.initial_state()};
  trajectory.states[1][0].p_WBr.z() = 0.9;
  trajectory.states[2][1].v_WBr.x() = 0.125;
  trajectory.dissipated_work = {0.0, 0.25, 1.0 / 3.0};
  const trajectory::TrajectoryTable table = trajectory::tabulate(model, trajectory);
  const int e = table.column("energy");
  const int w = table.column("dissipated_work");
  const int b = table.column("energy_balance");
  REQUIRE(e >= 0);
  CHECK(w == e + 1);
  CHECK(b == e + 2);
  CHECK(table.columns.size() == static_cast<std::size_t>(b + 1));
  const auto at = [&](std::size_t r, int c) { return table.rows[r][static_cast<std::size_t>(c)]; };
  for (std::size_t r = 0; r < 3; ++r) {
    CHECK(at(r, w) == trajectory.dissipated_work[r]);
    CHECK(at(r, b) == at(r, e) - at(0, e) + at(r, w));
  }
  // Body a 0.1 m lower: E changes by m g Δz = −2·9.81·0.1.
  // Tolerance: the difference of two energies of O(20) J (m g z + kinetic) is 1.96 J: each
  // energy's rounding ~20 × 1e-16 is ~1e-15 relative to the difference; 1e-12 leaves a factor
  // ~1000 for the energies' sums over the bodies.
  CHECK(at(1, e) - at(0, e) == Approx(-2.0 * 9.81 * 0.1).epsilon(1e-12));

  const testing::TempDir dir("contact-scene");
  const std::string path = (dir / "round_trip.csv").string();
  trajectory::write_csv(table, path);
  const trajectory::TrajectoryTable back = trajectory::read_csv(path);
  CHECK(back.columns == table.columns);
  REQUIRE(back.rows.size() == table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) CHECK(back.rows[r] == table.rows[r]);

  // Without W_d from the integrator the columns stay, as NaN: every file of a scene has the
  // same columns.
  trajectory.dissipated_work.clear();
  const trajectory::TrajectoryTable untracked = trajectory::tabulate(model, trajectory);
  CHECK(untracked.columns == table.columns);
  CHECK(std::isnan(untracked.rows[1][static_cast<std::size_t>(w)]));
}

TEST_CASE("a conservative model has no dissipation columns", "[app][csv][contact]") {
  const scene::Scene s = scene::parse_scene(kHead, "t.toml");
  CHECK_FALSE(s.model->dissipates());
  const std::vector<std::string> columns = trajectory::trajectory_columns(*s.model);
  CHECK(columns.back() == "energy");
}

}  // namespace flexref::app
