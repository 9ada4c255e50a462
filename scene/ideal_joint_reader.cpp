/// \file ideal_joint_reader.cpp
/// [[joint]] tables with model = "ideal" (scenes/README.md, docs/joints.md "Ideal joints") into
/// IdealJointSceneSpec, and [[spring]] tables into SpringSpec.
#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "scene/reader_parts.hpp"

namespace flexref::scene::detail {

namespace {

/// One end: a body (or, for the second end, the ground) and a point of it or a node.
constraint::JointEnd read_end(const Table& t, const BodyNames& names,
                              const std::vector<BodySpec>& bodies, const std::string& suffix,
                              bool first) {
  const std::string body_key = "body_" + suffix;
  const std::string point_key = "point_" + suffix;
  const std::string node_key = "node_" + suffix;
  constraint::JointEnd end;
  const toml::value* body = t.find(body_key);
  if (first) refuse_ground_first_end(t, "joint");
  const bool ground =
      !first && body != nullptr && body->is_string() && body->as_string() == "ground";
  if (!ground) end.body = names.resolve(t, body_key);
  if (t.has(node_key) && t.has(point_key)) {
    t.fail(point_key,
           "an end is a point or a node; expected " + point_key + " or " + node_key + ", not both");
  }
  if (t.has(node_key)) {
    if (ground) t.fail(node_key, "the ground has no nodes; expected " + point_key);
    const BodySpec& b = bodies[static_cast<std::size_t>(end.body)];
    end.node = read_node(t, node_key, b);
    end.p_BoP_B = b.description.flexible->modal.p_BoNode_B.col(end.node);
    return end;
  }
  end.p_BoP_B = t.vector3(point_key, ground ? "the joint point [x, y, z] in m, world frame"
                                            : "the joint point [x, y, z] in m, body_" + suffix +
                                                  " frame (from its origin)");
  return end;
}

}  // namespace

IdealJointSceneSpec read_ideal_joint(const Table& t, const BodyNames& names,
                                     const std::vector<BodySpec>& bodies, int index) {
  t.check_keys({"model", "name", "kind", "type", "body_a", "body_b", "point_a", "point_b", "node_a",
                "node_b", "axis_a", "axis_b", "length", "drive"});
  IdealJointSceneSpec spec;
  spec.source = source_of(t);
  constraint::IdealJointSpec& joint = spec.joint;
  joint.name = t.has("name") ? t.name("name", "the joint's name (its output columns' prefix)")
                             : "joint" + std::to_string(index);
  if (t.has("kind") && t.has("type")) {
    t.fail("type", "kind and type name the same thing; expected one of them");
  }
  const std::string_view kind_key = t.has("type") ? "type" : "kind";
  // In constraint::JointType's order.
  joint.type = static_cast<constraint::JointType>(t.choice(
      kind_key,
      {"spherical", "revolute", "prismatic", "cylindrical", "universal", "fixed", "distance"}, -1));
  joint.a = read_end(t, names, bodies, "a", true);
  joint.b = read_end(t, names, bodies, "b", false);
  if (joint.a.body == joint.b.body) {
    t.fail("body_b", "a joint joins two different bodies; expected another body or \"ground\"");
  }
  const bool axes = joint.type != constraint::JointType::kSpherical &&
                    joint.type != constraint::JointType::kDistance;
  const bool ground = joint.b.body == constraint::kGround;
  if (axes) {
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    const bool required = joint.type != constraint::JointType::kFixed;
    spec.axis_a = read_unit(t, "axis_a", required ? nullptr : &z,
                            "the joint axis [x, y, z], a unit vector, body_a frame");
    spec.axis_b = read_unit(t, "axis_b", required ? nullptr : &z,
                            ground ? "the joint axis [x, y, z], a unit vector, world frame"
                                   : "the joint axis [x, y, z], a unit vector, body_b frame");
  } else {
    reject_keys(t, {"axis_a", "axis_b"}, "applies only to joints with an axis");
  }
  if (joint.type == constraint::JointType::kDistance) {
    spec.length_given = t.has("length");
    joint.length = t.number_or("length", 0.0, Sign::kPositive,
                               "the rod's length L > 0 in m (default: the initial distance)");
  } else {
    reject_keys(t, {"length"}, "applies only to kind = \"distance\"");
  }
  if (t.has("drive")) {
    if (joint.type != constraint::JointType::kRevolute &&
        joint.type != constraint::JointType::kPrismatic) {
      t.fail("drive", "only revolute and prismatic joints can be driven");
    }
    const std::optional<Table> d =
        t.table("drive",
                "a table {law, rate[, spin_up_time]}: the relative angle (rad) or displacement "
                "(m) from the initial configuration");
    d->check_keys({"law", "rate", "spin_up_time"});
    joint.drive.active = true;
    const bool spin_up = d->choice("law", {"constant-rate", "spin-up"}, 0) == 1;
    joint.drive.law.kind =
        spin_up ? core::AngleLaw::Kind::kSpinUp : core::AngleLaw::Kind::kConstantRate;
    joint.drive.law.rate =
        d->number("rate", Sign::kAny, "the rate in rad/s (revolute) or m/s (prismatic)");
    if (spin_up) {
      joint.drive.law.spin_up_time =
          d->number("spin_up_time", Sign::kPositive, "a positive spin-up time in s");
    } else {
      reject_keys(*d, {"spin_up_time"}, "applies only to law = \"spin-up\"");
    }
  }
  return spec;
}

SpringSpec read_spring(const Table& t, const BodyNames& names) {
  t.check_keys(
      {"name", "body_a", "body_b", "point_a", "point_b", "stiffness", "damping", "rest_length"});
  SpringSpec spec;
  spec.source = source_of(t);
  if (t.has("name")) spec.name = t.name("name", "the spring's name (how messages name it)");
  refuse_ground_first_end(t, "spring");
  spec.body_a = names.resolve(t, "body_a");
  const toml::value* b = t.find("body_b");
  const bool ground = b != nullptr && b->is_string() && b->as_string() == "ground";
  spec.body_b = ground ? contact::kGround : names.resolve(t, "body_b");
  if (spec.body_b == spec.body_a) {
    t.fail("body_b", "a spring joins two different bodies; expected another body or \"ground\"");
  }
  spec.point_a = t.vector3("point_a", "the spring's end [x, y, z] in m, body_a frame");
  spec.point_b = t.vector3("point_b", ground ? "the spring's end [x, y, z] in m, world frame"
                                             : "the spring's end [x, y, z] in m, body_b frame");
  spec.parameters.stiffness = t.number("stiffness", Sign::kNonNegative, "a stiffness >= 0 in N/m");
  spec.parameters.damping =
      t.number_or("damping", 0.0, Sign::kNonNegative, "a damping >= 0 in N*s/m");
  spec.parameters.rest_length =
      t.number("rest_length", Sign::kNonNegative, "a rest length >= 0 in m");
  return spec;
}

}  // namespace flexref::scene::detail
