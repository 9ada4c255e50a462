/// \file contact_reader.cpp
/// [[contact]] and [[joint]] tables (scenes/README.md, docs/contact.md, docs/joints.md) into
/// ContactSpec and JointSpec.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "scene/reader_parts.hpp"

namespace flexref::scene::detail {

ContactSpec read_contact(const Table& t, const BodyNames& names) {
  t.check_keys({"kind",
                "body",
                "center",
                "centers",
                "radius",
                "point",
                "points",
                "body_b",
                "center_b",
                "radius_b",
                "plane_point",
                "plane_normal",
                "law",
                "stiffness",
                "exponent",
                "restitution",
                "reference_speed",
                "damping",
                "friction",
                "regularization_speed",
                "effective_mass"});
  const int kind = t.choice("kind", {"sphere-plane", "point-plane", "sphere-sphere"}, -1);
  const int body = names.resolve(t, "body");
  ContactSpec spec;
  spec.source = source_of(t);
  std::vector<contact::ContactPair>& pairs = spec.pairs;
  if (kind == 2) {
    reject_keys(t, {"centers", "point", "points", "plane_point", "plane_normal"},
                "applies only to sphere-plane and point-plane contacts");
    const int body_b = names.resolve(t, "body_b");
    if (body_b == body) {
      t.fail("body_b",
             "a sphere-sphere contact joins two different bodies; expected a body "
             "other than body");
    }
    const Eigen::Vector3d c_a =
        t.vector3("center", "the centre [x, y, z] of body's sphere in m, body frame");
    const double r_a = t.number("radius", Sign::kNonNegative, "a sphere radius >= 0 in m");
    const Eigen::Vector3d c_b =
        t.vector3("center_b", "the centre [x, y, z] of body_b's sphere in m, body_b's frame");
    const double r_b = t.number("radius_b", Sign::kNonNegative, "a sphere radius >= 0 in m");
    pairs.push_back(contact::ContactPair::sphere_sphere(body, c_a, r_a, body_b, c_b, r_b));
  } else {
    reject_keys(t, {"body_b", "center_b", "radius_b"}, "applies only to sphere-sphere contacts");
    const Eigen::Vector3d p_WQ = t.vector3_or("plane_point", Eigen::Vector3d::Zero(),
                                              "a point [x, y, z] of the plane in m, world frame");
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d n_W =
        read_unit(t, "plane_normal", &up,
                  "the plane's unit normal [x, y, z] toward the free side, world frame");
    if (kind == 0) {
      reject_keys(t, {"point", "points"},
                  "a sphere-plane contact is given by center(s) and radius");
      const std::vector<Eigen::Vector3d> centers =
          read_vector_list(t, "center", "centers", "the sphere centre [x, y, z] in m, body frame");
      const double r = t.number("radius", Sign::kNonNegative, "a sphere radius >= 0 in m");
      for (const Eigen::Vector3d& c : centers) {
        pairs.push_back(contact::ContactPair::sphere_plane(body, c, r, p_WQ, n_W));
      }
    } else {
      reject_keys(t, {"center", "centers", "radius"}, "a point-plane contact is given by point(s)");
      const std::vector<Eigen::Vector3d> points =
          read_vector_list(t, "point", "points", "the contact point [x, y, z] in m, body frame");
      for (const Eigen::Vector3d& p : points) {
        pairs.push_back(contact::ContactPair::point_plane(body, p, p_WQ, n_W));
      }
    }
  }
  // Absent: derived from the bodies' masses when the model is built (build_model.hpp).
  if (t.has("effective_mass")) {
    spec.effective_mass =
        t.number("effective_mass", Sign::kPositive, "a positive effective mass in kg");
  }

  ContactLawSpec& law = spec.law;
  law.linear = t.choice("law", {"hunt-crossley", "linear"}, 0) == 1;
  law.stiffness =
      t.number_or("stiffness", 1e6, Sign::kPositive,
                  law.linear ? "a positive stiffness in N/m" : "a positive stiffness in N/m^n");
  if (t.has("restitution")) {
    const double e =
        t.number("restitution", Sign::kPositive, "a restitution coefficient in (0, 1]");
    if (e > 1.0) {
      t.fail("restitution", "expected a restitution coefficient in (0, 1], got " + format(e));
    }
    law.restitution = e;
  }
  if (law.linear) {
    reject_keys(t, {"exponent", "reference_speed"}, "applies only to law = \"hunt-crossley\"");
    if (t.has("damping") && t.has("restitution")) {
      t.fail("damping",
             "the linear law takes either damping or restitution; expected one "
             "of them, not both");
    }
    if (t.has("damping")) {
      law.damping = t.number("damping", Sign::kNonNegative, "a damping >= 0 in N*s/m");
    }
  } else {
    reject_keys(t, {"damping"},
                "applies only to law = \"linear\" (Hunt-Crossley damping follows from "
                "restitution and reference_speed)");
    law.exponent = t.number_or("exponent", 1.5, Sign::kPositive, "an exponent >= 1");
    if (law.exponent < 1.0) {
      t.fail("exponent", "expected an exponent >= 1, got " + format(law.exponent));
    }
    law.reference_speed = t.number_or("reference_speed", 1.0, Sign::kPositive,
                                      "a positive reference impact speed in m/s");
  }
  spec.friction.mu = t.number_or("friction", 0.0, Sign::kNonNegative,
                                 "a friction coefficient mu >= 0 (0: frictionless)");
  spec.friction.v_reg = t.number_or("regularization_speed", 1e-3, Sign::kPositive,
                                    "a positive regularization speed in m/s");
  return spec;
}

// --- [[joint]] -----------------------------------------------------------------------------

JointSpec read_joint(const Table& t, const BodyNames& names) {
  t.check_keys({"kind", "body_a", "body_b", "point_a", "point_b", "axis_a", "axis_b", "stiffness",
                "damping", "angular_stiffness", "angular_damping"});
  const bool revolute = t.choice("kind", {"spherical", "revolute"}, -1) == 1;
  contact::BushingEnd a;
  contact::BushingEnd b;
  a.body = names.resolve(t, "body_a");
  const toml::value* vb = t.find("body_b");
  if (vb != nullptr && vb->is_string() && vb->as_string() == "ground") {
    b.body = contact::kGround;
  } else {
    b.body = names.resolve(t, "body_b");
    if (b.body == a.body) {
      t.fail("body_b",
             "a joint joins two different bodies; expected another body or "
             "\"ground\"");
    }
  }
  const bool ground = b.body == contact::kGround;
  a.point = t.vector3("point_a", "the joint point [x, y, z] in m on body_a, body frame");
  b.point = t.vector3("point_b", ground ? "the joint point [x, y, z] in m, world frame (ground)"
                                        : "the joint point [x, y, z] in m on body_b, body frame");
  contact::BushingParameters p;
  p.stiffness = t.number_or("stiffness", contact::BushingParameters::kDefaultStiffness,
                            Sign::kPositive, "a positive stiffness in N/m");
  p.damping = t.number_or("damping", 0.0, Sign::kNonNegative, "a damping >= 0 in N*s/m");
  if (revolute) {
    a.axis =
        read_unit(t, "axis_a", nullptr, "the hinge axis [x, y, z], a unit vector, body_a frame");
    b.axis = read_unit(t, "axis_b", nullptr,
                       ground ? "the hinge axis [x, y, z], a unit vector, world frame (ground)"
                              : "the hinge axis [x, y, z], a unit vector, body_b frame");
    p.angular_stiffness =
        t.number_or("angular_stiffness", contact::BushingParameters::kDefaultAngularStiffness,
                    Sign::kNonNegative, "an angular stiffness >= 0 in N*m/rad");
    p.angular_damping = t.number_or("angular_damping", 0.0, Sign::kNonNegative,
                                    "an angular damping >= 0 in N*m*s/rad");
  } else {
    reject_keys(t, {"axis_a", "axis_b", "angular_stiffness", "angular_damping"},
                "applies only to kind = \"revolute\"");
  }

  JointSpec spec;
  spec.revolute = revolute;
  spec.a = a;
  spec.b = b;
  spec.parameters = p;
  spec.source = source_of(t);
  return spec;
}

}  // namespace flexref::scene::detail
