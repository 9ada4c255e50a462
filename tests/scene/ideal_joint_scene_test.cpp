/// \file ideal_joint_scene_test.cpp
/// Bad ideal joints in scene files (docs/joints.md, "Scene"): an end on an unknown body or node,
/// an axis of zero length, an initial state that violates the joint beyond 1e-6 — each refused
/// with file, line and key; and the tolerance's other side, accepted.
#include <catch2/catch.hpp>
#include <string>

#include "core/error.hpp"
#include "core/step_limit.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/scene_error_checks.hpp"

namespace flexref::scene {
namespace {

using testing::replace_first;
using testing::require_scene_error;

// Lines 1-4 [scene], 5-8 the rigid body "a", 9-18 a revolute joint to the ground at its origin:
// valid as it stands.
const std::string kIdealJointScene =
    "[scene]\n"
    "name = \"t\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n"
    "[[body]]\n"
    "name = \"a\"\n"
    "mass = 1.0\n"
    "inertia = [1.0, 1.0, 1.0]\n"
    "[[joint]]\n"
    "name = \"hinge\"\n"
    "model = \"ideal\"\n"
    "kind = \"revolute\"\n"
    "body_a = \"a\"\n"
    "point_a = [0.0, 0.0, 0.0]\n"
    "body_b = \"ground\"\n"
    "point_b = [0.0, 0.0, 0.0]\n"
    "axis_a = [0.0, 0.0, 1.0]\n"
    "axis_b = [0.0, 0.0, 1.0]\n";

// A flexible body "f" (lines 5-15: hub, then [body.beam] from line 9; its beam's tip node4 at
// (1, 0, 0)) and a spherical joint from that node to the ground (lines 16-23).
const std::string kIdealJointFlexibleScene =
    "[scene]\n"
    "name = \"t\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n"
    "[[body]]\n"
    "name = \"f\"\n"
    "mass = 10.0\n"
    "inertia = [0.5, 0.5, 1.0]\n"
    "[body.beam]\n"
    "length = 1.0\n"
    "elements = 4\n"
    "EA = 1e5\n"
    "EI = 3.2\n"
    "rho_A = 1.0\n"
    "modes = 2\n"
    "[[joint]]\n"
    "name = \"pin\"\n"
    "model = \"ideal\"\n"
    "kind = \"spherical\"\n"
    "body_a = \"f\"\n"
    "node_a = \"node4\"\n"
    "body_b = \"ground\"\n"
    "point_b = [1.0, 0.0, 0.0]\n";

}  // namespace

TEST_CASE("ideal joints: the valid test scene reads", "[scene][joints]") {
  const Scene s = parse_scene(kIdealJointScene, "good.toml");
  REQUIRE(s.model->has_constraints());
  CHECK(s.model->constraints()->joint_name(0) == "hinge");
}

TEST_CASE("ideal joints: bad input names file, line and key", "[scene][joints]") {
  SECTION("an end on an unknown body") {
    require_scene_error(replace_first(kIdealJointScene, "body_a = \"a\"", "body_a = \"b\""), 13,
                        "joint[1].body_a", "no [[body]] named \"b\"; expected one of \"a\"");
    require_scene_error(replace_first(kIdealJointScene, "body_b = \"ground\"", "body_b = \"grnd\""),
                        15, "joint[1].body_b", "no [[body]] named \"grnd\"");
  }
  SECTION("the ground as the first end: refused with what to do") {
    // Before: "no [[body]] named \"ground\"", as if a body were missing.
    std::string swapped = replace_first(kIdealJointScene, "body_a = \"a\"", "body_a = \"ground\"");
    swapped = replace_first(swapped, "body_b = \"ground\"", "body_b = \"a\"");
    require_scene_error(swapped, 13, "joint[1].body_a",
                        "the first end of a joint must be a body (its reactions are reported on "
                        "it); the ground can only be the second end: swap the ends, body_a = "
                        "\"a\" and body_b = \"ground\", exchanging point_a and point_b, "
                        "axis_a and axis_b");
  }
  SECTION("an end on a node of a rigid body, or on an unknown node") {
    require_scene_error(
        replace_first(kIdealJointScene, "point_a = [0.0, 0.0, 0.0]", "node_a = \"tip\""), 14,
        "joint[1].node_a", "applies only to flexible bodies");
    require_scene_error(
        replace_first(kIdealJointFlexibleScene, "node_a = \"node4\"", "node_a = \"node9\""), 21,
        "joint[1].node_a", "no node named \"node9\" in the modal data of body \"f\"");
  }
  SECTION("an axis of zero length") {
    require_scene_error(
        replace_first(kIdealJointScene, "axis_a = [0.0, 0.0, 1.0]", "axis_a = [0, 0, 0]"), 17,
        "joint[1].axis_a", "got norm 0");
    require_scene_error(
        replace_first(kIdealJointScene, "axis_b = [0.0, 0.0, 1.0]", "axis_b = [0, 0, 0]"), 18,
        "joint[1].axis_b", "got norm 0");
  }
  SECTION("an initial state that violates the joint beyond 1e-6, at either level") {
    // The joint point 1e-3 m off the body's: relative 1e-3 of the 1 m length scale (no arm: 1 m).
    require_scene_error(
        replace_first(kIdealJointScene, "point_b = [0.0, 0.0, 0.0]", "point_b = [0.0, 0.0, 1e-3]"),
        9, "joint[1]", "violates joint 'hinge' at position level");
    // The body turning about x, which the hinge about z forbids.
    require_scene_error(replace_first(kIdealJointScene, "inertia = [1.0, 1.0, 1.0]\n",
                                      "inertia = [1.0, 1.0, 1.0]\n"
                                      "angular_velocity = [1.0, 0.0, 0.0]\n"),
                        10, "joint[1]", "violates joint 'hinge' at velocity level");
  }
}

TEST_CASE("ideal joints: a violation within 1e-6 is projected, a larger one when the scene asks",
          "[scene][joints]") {
  // 1e-7 m off: below the 1e-6 relative tolerance, accepted and projected onto the joint.
  const Scene small = parse_scene(
      replace_first(kIdealJointScene, "point_b = [0.0, 0.0, 0.0]", "point_b = [0.0, 0.0, 1e-7]"),
      "small.toml");
  // The projection removes it to Newton's tolerance: round-off of the 1e-7 correction.
  CHECK(small.model->consistent_initial_state().projection.position > 0.9e-7);
  core::Workspace ws = small.model->make_workspace();
  CHECK(small.model->constraint_violations(0.0, small.model->initial_state(), ws)[0][0] < 1e-15);
  // 1e-3 m off with project_initial_state = true: projected instead of refused.
  const Scene projected = parse_scene(
      replace_first(replace_first(kIdealJointScene, "point_b = [0.0, 0.0, 0.0]",
                                  "point_b = [0.0, 0.0, 1e-3]"),
                    "output_step = 0.1\n", "output_step = 0.1\nproject_initial_state = true\n"),
      "projected.toml");
  CHECK(projected.model->consistent_initial_state().projection.position > 0.9e-3);
}

}  // namespace flexref::scene

namespace flexref::scene {
namespace {

// [[spring]] tables after the joint scene (lines 19-25, then 26-32).
const std::string kSpring =
    "[[spring]]\n"
    "body_a = \"a\"\n"
    "point_a = [1.0, 0.0, 0.0]\n"
    "body_b = \"ground\"\n"
    "point_b = [2.0, 0.0, 0.0]\n"
    "stiffness = 100.0\n"
    "rest_length = 1.0\n";

TEST_CASE("springs are named as springs, by their name or their table", "[scene][joints]") {
  SECTION("unnamed: spring[k] of its [[spring]] table, never joint[k]") {
    // Before: the spring's mode was labelled "joint[1]", which in a scene with joints named
    // another table (Andrews' squeezer: "of joint[1]" was its revolute joint O).
    const Scene s = parse_scene(kIdealJointScene + kSpring + kSpring, "springs.toml");
    const std::vector<core::PenaltyMode> modes = core::penalty_modes(*s.model);
    REQUIRE(modes.size() == 2);
    CHECK(modes[0].label == "spring[1]");
    CHECK(modes[0].kind == "spring");
    CHECK(modes[1].label == "spring[2]");
    CHECK(modes[1].element == 1);
    CHECK(core::explicit_step_limit(*s.model).what == "spring[1]");
    CHECK(s.model->elements()[0]->describe_with_names(s.model->bodies()) ==
          "spring-damper: body 'a' point (1, 0, 0) to ground point (2, 0, 0), k = 100 N/m, c = 0 "
          "N*s/m, rest length 1 m");
  }
  SECTION("named: spring 'NAME'") {
    const Scene s = parse_scene(kIdealJointScene + kSpring + "name = \"c0\"\n", "springs.toml");
    CHECK(core::penalty_modes(*s.model).at(0).label == "spring 'c0'");
  }
  SECTION("bad names and the ground as the first end") {
    require_scene_error(
        kIdealJointScene + kSpring + "name = \"c0\"\n" + kSpring + "name = \"c0\"\n", 34,
        "spring[2].name", "duplicate spring name \"c0\"");
    require_scene_error(kIdealJointScene + kSpring + "name = \"c 0\"\n", 26, "spring[1].name");
    require_scene_error(
        replace_first(replace_first(kIdealJointScene + kSpring, "body_a = \"a\"\npoint_a = [1.0",
                                    "body_a = \"ground\"\npoint_a = [1.0"),
                      "body_b = \"ground\"\npoint_b = [2.0", "body_b = \"a\"\npoint_b = [2.0"),
        20, "spring[1].body_a",
        "the first end of a spring must be a body; the ground can only be the "
        "second end: swap the ends, body_a = "
        "\"a\" and body_b = \"ground\", exchanging point_a and point_b");
  }
}

}  // namespace
}  // namespace flexref::scene
