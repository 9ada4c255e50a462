/// \file contact_reader.cpp
/// [[contact]] and [[joint]] tables (scenes/README.md, docs/contact.md, docs/joints.md) into
/// ContactSpec and JointSpec.
#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "scene/reader_parts.hpp"

namespace flexref::scene::detail {

namespace {

/// [[contact]] kind = "gap-support" (contact/gap_support.hpp).
GapSupportSpec read_gap_support(const Table& t, int body, const std::vector<BodySpec>& bodies) {
  reject_keys(t,
              {"center", "centers", "radius", "points", "body_b", "center_b", "radius_b", "node_b",
               "plane_point"},
              "does not apply to a gap support (node or point, axis_point, axis, clearance)");
  GapSupportSpec gap;
  gap.body = body;
  const BodySpec& b = bodies[static_cast<std::size_t>(body)];
  if (t.has("node") && t.has("point")) {
    t.fail("point", "a gap support acts at a node or at a point; expected one of them, not both");
  }
  if (t.has("node")) {
    gap.node = read_node(t, "node", b);
    gap.p_BoN_B = b.description.flexible->modal.p_BoNode_B.col(gap.node);
  } else {
    gap.p_BoN_B = t.vector3("point", "the supported point [x, y, z] in m, body frame (or node)");
  }
  contact::GapSupportGeometry& g = gap.geometry;
  g.kind = t.choice("shape", {"circular", "planar"}, 0) == 0
               ? contact::GapSupportGeometry::Kind::kCircular
               : contact::GapSupportGeometry::Kind::kPlanar;
  g.p_WS = t.vector3("axis_point", "a point [x, y, z] of the support axis in m, world frame");
  g.a_W = read_unit(t, "axis", nullptr, "the support axis [x, y, z], a unit vector, world frame");
  g.clearance = t.number("clearance", Sign::kPositive, "a positive radial clearance in m");
  if (g.kind == contact::GapSupportGeometry::Kind::kPlanar) {
    g.m_W = read_unit(t, "plane_normal", nullptr,
                      "the unit normal [x, y, z] of the two support planes, world frame");
    if (std::abs(g.m_W.dot(g.a_W)) > 1.0 - 1e-6) {
      t.fail("plane_normal",
             "the planes' normal is parallel to the axis; expected a normal "
             "across the axis");
    }
  } else {
    reject_keys(t, {"plane_normal"}, "applies only to shape = \"planar\"");
  }
  return gap;
}

/// The `wear` table of a [[contact]] (docs/wear.md): the law and its parameters, checked against
/// the contact's kind. `gap` is the contact's gap support (nullopt for point and sphere
/// contacts).
core::WearLaw read_wear(const Table& contact, const std::optional<GapSupportSpec>& gap,
                        std::size_t points) {
  const std::optional<Table> table = contact.table(
      "wear", "a wear law { law = \"archard\" | \"work-rate\", coefficient = ..., ... }");
  const Table& t = *table;
  if (!contact.has("name")) {
    contact.fail("wear",
                 "a wear law needs a named contact (its depths are written as C.depth1, ...); "
                 "expected a name = \"...\" key");
  }
  t.check_keys({"law", "coefficient", "hardness", "area", "acceleration", "sectors", "thickness",
                "radius", "depth"});
  core::WearLaw law;
  law.kind = t.choice("law", {"archard", "work-rate"}, -1) == 0 ? core::WearLaw::Kind::kArchard
                                                                : core::WearLaw::Kind::kWorkRate;
  const bool archard = law.kind == core::WearLaw::Kind::kArchard;
  law.coefficient = t.number("coefficient", Sign::kPositive,
                             archard ? "a positive dimensionless wear coefficient k"
                                     : "a positive work-rate coefficient K_w in 1/Pa (m^3/(N*m))");
  if (archard) {
    law.hardness = t.number("hardness", Sign::kPositive, "a positive hardness H in Pa");
  } else {
    reject_keys(t, {"hardness"}, "applies only to law = \"archard\"");
  }
  law.acceleration = t.number_or("acceleration", 1.0, Sign::kPositive,
                                 "a positive acceleration factor (multiplies the coefficient)");
  if (gap) {
    reject_keys(t, {"area"},
                "a gap support wears by sectors of area (2 pi radius / sectors) * thickness");
    if (gap->geometry.kind != contact::GapSupportGeometry::Kind::kCircular) {
      contact.fail("wear",
                   "a wear law applies to a circular gap support only (shape = "
                   "\"circular\")");
    }
    const double sectors =
        t.number("sectors", Sign::kPositive, "a whole number of angular sectors >= 1");
    if (sectors < 1.0 || sectors != std::floor(sectors) || sectors > 1e5) {
      t.fail("sectors",
             "expected a whole number of angular sectors in [1, 100000], got " + format(sectors));
    }
    law.sectors = static_cast<int>(sectors);
    law.thickness = t.number("thickness", Sign::kPositive, "the support's positive thickness in m");
    law.radius = t.number("radius", Sign::kPositive, "the hole's positive radius in m");
  } else {
    reject_keys(t, {"sectors", "thickness", "radius"}, "applies only to a gap support");
    law.area =
        t.number("area", Sign::kPositive, "the positive area of each contact point's pin in m^2");
  }
  if (t.has("depth")) {
    // The worn depths at t = 0 (the support or pins as inspected), one per sector or point.
    const std::size_t n = gap ? static_cast<std::size_t>(law.sectors) : points;
    const std::string expected = "an array of " + std::to_string(n) +
                                 " worn depths >= 0 in m, one per " + (gap ? "sector" : "point");
    const toml::value* v = t.find("depth");
    if (!v->is_array() || v->as_array().size() != n) {
      t.fail("depth", "expected " + expected + ", got " + scene_toml::describe(*v));
    }
    for (const toml::value& x : v->as_array()) {
      law.initial_depth.push_back(t.to_number(x, "depth", Sign::kNonNegative, expected));
    }
  }
  return law;
}

}  // namespace

ContactSpec read_contact(const Table& t, const BodyNames& names,
                         const std::vector<BodySpec>& bodies) {
  t.check_keys({"kind",           "name",        "node",
                "node_b",         "axis_point",  "axis",
                "clearance",      "shape",       "body",
                "center",         "centers",     "radius",
                "point",          "points",      "body_b",
                "center_b",       "radius_b",    "plane_point",
                "plane_normal",   "law",         "stiffness",
                "exponent",       "restitution", "reference_speed",
                "damping",        "friction",    "regularization_speed",
                "effective_mass", "wear"});
  const int kind =
      t.choice("kind", {"sphere-plane", "point-plane", "sphere-sphere", "gap-support"}, -1);
  const int body = names.resolve(t, "body");
  ContactSpec spec;
  spec.source = source_of(t);
  if (t.has("name")) spec.name = t.name("name", "a contact name (the prefix of its wear columns)");
  std::vector<contact::ContactPair>& pairs = spec.pairs;
  if (kind != 3) {
    reject_keys(t, {"axis_point", "axis", "clearance", "shape"},
                "applies only to kind = \"gap-support\"");
  }
  // A sphere (or point) at a node of a flexible body: the node's position is its centre.
  const BodySpec& body_spec = bodies[static_cast<std::size_t>(body)];
  const auto node_position = [&](int node) {
    return Eigen::Vector3d(body_spec.description.flexible->modal.p_BoNode_B.col(node));
  };
  if (kind == 3) {
    spec.gap = read_gap_support(t, body, bodies);
  } else if (kind == 2) {
    reject_keys(t, {"centers", "point", "points", "plane_point", "plane_normal"},
                "applies only to sphere-plane and point-plane contacts");
    const int body_b = names.resolve(t, "body_b");
    if (body_b == body) {
      t.fail("body_b",
             "a sphere-sphere contact joins two different bodies; expected a body "
             "other than body");
    }
    if (t.has("node") && t.has("center")) {
      t.fail("center", "a node sphere is centred at its node; expected either center or node");
    }
    if (t.has("node_b") && t.has("center_b")) {
      t.fail("center_b",
             "a node sphere is centred at its node; expected either center_b or node_b");
    }
    const int node_a = t.has("node") ? read_node(t, "node", body_spec) : -1;
    const int node_b =
        t.has("node_b") ? read_node(t, "node_b", bodies[static_cast<std::size_t>(body_b)]) : -1;
    const Eigen::Vector3d c_a =
        node_a >= 0 ? node_position(node_a)
                    : t.vector3("center", "the centre [x, y, z] of body's sphere in m, body frame");
    const double r_a = t.number("radius", Sign::kNonNegative, "a sphere radius >= 0 in m");
    const Eigen::Vector3d c_b =
        node_b >= 0
            ? Eigen::Vector3d(bodies[static_cast<std::size_t>(body_b)]
                                  .description.flexible->modal.p_BoNode_B.col(node_b))
            : t.vector3("center_b", "the centre [x, y, z] of body_b's sphere in m, body_b's frame");
    const double r_b = t.number("radius_b", Sign::kNonNegative, "a sphere radius >= 0 in m");
    pairs.push_back(contact::ContactPair::sphere_sphere(body, c_a, r_a, body_b, c_b, r_b));
    pairs.back().node_a.node = node_a;
    pairs.back().node_b.node = node_b;
  } else {
    reject_keys(t, {"body_b", "center_b", "radius_b", "node_b"},
                "applies only to sphere-sphere contacts");
    const Eigen::Vector3d p_WQ = t.vector3_or("plane_point", Eigen::Vector3d::Zero(),
                                              "a point [x, y, z] of the plane in m, world frame");
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d n_W =
        read_unit(t, "plane_normal", &up,
                  "the plane's unit normal [x, y, z] toward the free side, world frame");
    if (kind == 0) {
      reject_keys(t, {"point", "points"},
                  "a sphere-plane contact is given by center(s) (or node) and radius");
      if (t.has("node")) reject_keys(t, {"center", "centers"}, "a node sphere is at its node");
      const int node = t.has("node") ? read_node(t, "node", body_spec) : -1;
      const std::vector<Eigen::Vector3d> centers =
          node >= 0 ? std::vector<Eigen::Vector3d>{node_position(node)}
                    : read_vector_list(t, "center", "centers",
                                       "the sphere centre [x, y, z] in m, body frame");
      const double r = t.number("radius", Sign::kNonNegative, "a sphere radius >= 0 in m");
      for (const Eigen::Vector3d& c : centers) {
        pairs.push_back(contact::ContactPair::sphere_plane(body, c, r, p_WQ, n_W));
        pairs.back().node_b.node = node;
      }
    } else {
      reject_keys(t, {"center", "centers", "radius"},
                  "a point-plane contact is given by point(s) or node");
      if (t.has("node")) reject_keys(t, {"point", "points"}, "a node point is at its node");
      const int node = t.has("node") ? read_node(t, "node", body_spec) : -1;
      const std::vector<Eigen::Vector3d> points =
          node >= 0 ? std::vector<Eigen::Vector3d>{node_position(node)}
                    : read_vector_list(t, "point", "points",
                                       "the contact point [x, y, z] in m, body frame");
      for (const Eigen::Vector3d& p : points) {
        pairs.push_back(contact::ContactPair::point_plane(body, p, p_WQ, n_W));
        pairs.back().node_b.node = node;
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
  if (t.has("wear")) spec.wear = read_wear(t, spec.gap, spec.pairs.size());
  return spec;
}

// --- [[joint]] -----------------------------------------------------------------------------

JointSpec read_joint(const Table& t, const BodyNames& names) {
  t.check_keys({"model", "name", "kind", "body_a", "body_b", "point_a", "point_b", "axis_a",
                "axis_b", "stiffness", "damping", "angular_stiffness", "angular_damping"});
  const bool revolute = t.choice("kind", {"spherical", "revolute"}, -1) == 1;
  contact::BushingEnd a;
  contact::BushingEnd b;
  refuse_ground_first_end(t, "joint");
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
  if (t.has("name")) spec.name = t.name("name", "the joint's name (how messages name it)");
  spec.revolute = revolute;
  spec.a = a;
  spec.b = b;
  spec.parameters = p;
  spec.source = source_of(t);
  return spec;
}

}  // namespace flexref::scene::detail
