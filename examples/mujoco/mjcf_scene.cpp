#include "examples/mujoco/mjcf_scene.hpp"

#include <Eigen/Geometry>
#include <cstdio>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "examples/engine_adapter/engine.hpp"
#include "examples/engine_adapter/scene_mapping.hpp"

namespace flexref::engines {
namespace {

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

std::string vector3(const Eigen::Vector3d& v) {
  return number(v.x()) + " " + number(v.y()) + " " + number(v.z());
}

std::string quaternion(const Eigen::Quaterniond& q) {
  return number(q.w()) + " " + number(q.x()) + " " + number(q.y()) + " " + number(q.z());
}

Eigen::Quaterniond attitude(const RigidBodyInput& b) {
  return Eigen::Quaterniond(b.e_WB[0], b.e_WB[1], b.e_WB[2], b.e_WB[3]);
}

/// The largest distance of an ideal joint's point from its body's origin: the arm of a
/// revolute loop's second connect (1 m when every point is at its body's origin).
double joint_arm(const RigidScene& scene) {
  double arm = 0.0;
  for (const IdealJointInput& j : scene.ideal_joints) {
    arm = std::max(arm, j.a.p_BoP_B.norm());
    if (j.b.body >= 0) arm = std::max(arm, j.b.p_BoP_B.norm());
  }
  return arm > 0.0 ? arm : 1.0;
}

class MjcfWriter {
 public:
  MjcfWriter(const RigidScene& scene, std::ostringstream& x) : scene_(scene), x_(x) {}

  /// The site names of the bushings, springs and rods: "<element><index>_a" / "_b".
  void sites_on(int body, const std::string& indent) {
    const auto site = [&](const std::string& name, const Eigen::Vector3d& p) {
      x_ << indent << "<site name=\"" << name << "\" pos=\"" << vector3(p) << "\"/>\n";
    };
    for (std::size_t j = 0; j < scene_.springs.size(); ++j) {
      const SpringInput& s = scene_.springs[j];
      if (s.body_a == body) site("joint" + std::to_string(j) + "_a", s.point_a);
      if (s.body_b == body) site("joint" + std::to_string(j) + "_b", s.point_b);
    }
    for (std::size_t j = 0; j < scene_.linear_springs.size(); ++j) {
      const LinearSpringInput& s = scene_.linear_springs[j];
      if (s.body_a == body) site("spring" + std::to_string(j) + "_a", s.point_a);
      if (s.body_b == body) site("spring" + std::to_string(j) + "_b", s.point_b);
    }
    for (int l : scene_.loops) {
      const IdealJointInput& j = scene_.ideal_joints[static_cast<std::size_t>(l)];
      if (j.kind != IdealJointKind::kDistance) continue;
      if (j.a.body == body) site("rod" + std::to_string(l) + "_a", j.a.p_BoP_B);
      if (j.b.body == body) site("rod" + std::to_string(l) + "_b", j.b.p_BoP_B);
    }
  }

  /// Body b and its subtree; `indent` is the body element's indentation.
  void body(int b, const std::string& indent) {
    const RigidBodyInput& d = scene_.bodies[static_cast<std::size_t>(b)];
    const TreeLink link =
        scene_.tree.empty() ? TreeLink{} : scene_.tree[static_cast<std::size_t>(b)];
    Eigen::Vector3d pos = d.p_WBo;
    Eigen::Quaterniond quat = attitude(d);
    if (link.parent >= 0) {
      // Placed at the initial pose relative to the parent: every joint coordinate starts at 0.
      const RigidBodyInput& p = scene_.bodies[static_cast<std::size_t>(link.parent)];
      const Eigen::Quaterniond q_WP = attitude(p).normalized();
      pos = q_WP.conjugate() * (d.p_WBo - p.p_WBo);
      quat = q_WP.conjugate() * attitude(d).normalized();
    }
    x_ << indent << "<body name=\"" << d.name << "\" pos=\"" << vector3(pos) << "\" quat=\""
       << (link.parent >= 0 ? quaternion(quat)
                            : number(d.e_WB[0]) + " " + number(d.e_WB[1]) + " " +
                                  number(d.e_WB[2]) + " " + number(d.e_WB[3]))
       << "\">\n";
    const std::string in = indent + "  ";
    if (link.joint >= 0) {
      tree_joint(b, link, in);
    } else if (!d.pivot) {
      x_ << in << "<freejoint name=\"" << d.name << "_free\"/>\n";
    } else {
      x_ << in << "<joint name=\"" << d.name << "_pivot\" type=\"ball\" pos=\""
         << vector3(d.p_BoPivot_B) << "\" damping=\"0\" armature=\"0\" stiffness=\"0\"/>\n";
    }
    const Eigen::Matrix3d& I = d.I_Bcm_B;
    x_ << in << "<inertial pos=\"" << vector3(d.p_BoBcm_B) << "\" mass=\"" << number(d.mass)
       << "\" fullinertia=\"" << number(I(0, 0)) << " " << number(I(1, 1)) << " " << number(I(2, 2))
       << " " << number(I(0, 1)) << " " << number(I(0, 2)) << " " << number(I(1, 2)) << "\"/>\n";
    sites_on(b, in);
    for (int c : scene_.tree_order) {
      if (!scene_.tree.empty() && scene_.tree[static_cast<std::size_t>(c)].parent == b) body(c, in);
    }
    x_ << indent << "</body>\n";
  }

  /// The joint that places body b below its parent (mjcf_scene.hpp: the mapping).
  void tree_joint(int b, const TreeLink& link, const std::string& in) {
    const IdealJointInput& j = scene_.ideal_joints[static_cast<std::size_t>(link.joint)];
    const JointEndInput& child = link.child_is_a ? j.a : j.b;
    const JointEndInput& parent = link.child_is_a ? j.b : j.a;
    const Eigen::Vector3d axis = child.R_BJ.col(2);
    const auto joint = [&](const std::string& suffix, const char* type, const Eigen::Vector3d& a) {
      x_ << in << "<joint name=\"" << j.name << suffix << "\" type=\"" << type << "\" pos=\""
         << vector3(child.p_BoP_B) << "\"";
      if (std::string(type) != "ball") x_ << " axis=\"" << vector3(a) << "\"";
      x_ << " limited=\"false\" damping=\"0\" armature=\"0\" stiffness=\"0\"/>\n";
    };
    switch (j.kind) {
      case IdealJointKind::kSpherical:
        joint("", "ball", axis);
        break;
      case IdealJointKind::kRevolute:
        joint("", "hinge", axis);
        break;
      case IdealJointKind::kPrismatic:
        joint("", "slide", axis);
        break;
      case IdealJointKind::kCylindrical:
        joint("_hinge", "hinge", axis);
        joint("_slide", "slide", axis);
        break;
      case IdealJointKind::kUniversal: {
        // The parent's axis as the child's frame sees it in the initial configuration.
        const Eigen::Quaterniond q_WC =
            attitude(scene_.bodies[static_cast<std::size_t>(b)]).normalized();
        Eigen::Quaterniond q_WP = Eigen::Quaterniond::Identity();
        if (parent.body >= 0) {
          q_WP = attitude(scene_.bodies[static_cast<std::size_t>(parent.body)]).normalized();
        }
        joint("_parent_axis", "hinge", q_WC.conjugate() * (q_WP * parent.R_BJ.col(2)));
        joint("_child_axis", "hinge", axis);
        break;
      }
      case IdealJointKind::kFixed:
        break;  // welded to the parent: no joint
      case IdealJointKind::kDistance:
        throw std::logic_error("a distance joint is never a tree joint");
    }
  }

 private:
  const RigidScene& scene_;
  std::ostringstream& x_;
};

}  // namespace

std::string ConstraintSoftness::attributes(double dt) const {
  const double timeconst = solref[0] == 0.0 ? 2.0 * dt : solref[0];
  return "solref=\"" + number(timeconst) + " " + number(solref[1]) + "\" solimp=\"" +
         number(solimp[0]) + " " + number(solimp[1]) + " " + number(solimp[2]) + " " +
         number(solimp[3]) + " " + number(solimp[4]) + "\"";
}

void check_mujoco_mappable(const scene::Scene& scene) {
  check_rigid_scene(scene, "MuJoCo");
  if (!scene.spec.contacts.empty()) {
    throw MappingError(scene.spec.contacts.front().source,
                       "MuJoCo's contacts are soft constraints (solref/solimp), not flexref's "
                       "penalty laws (Hunt-Crossley or linear spring-dashpot with regularized "
                       "friction); no exact mapping exists, so contacts are not mapped");
  }
  for (const scene::JointSpec& joint : scene.spec.joints) {
    if (joint.revolute) {
      throw MappingError(joint.source,
                         "a revolute bushing's angular spring k_theta (1 - cos alpha) has no "
                         "MuJoCo element; only undamped spherical bushings are mapped");
    }
    if (joint.parameters.damping != 0.0) {
      throw MappingError(joint.source,
                         "a damped spherical bushing acts on the 3D relative velocity; a MuJoCo "
                         "tendon damps only its length rate, so only damping = 0 is mapped");
    }
  }
  for (const scene::IdealJointSceneSpec& joint : scene.spec.ideal_joints) {
    if (joint.joint.drive.active) {
      scene::SpecSource source = joint.source;
      source.path += ".drive";
      throw MappingError(source,
                         "MuJoCo cannot prescribe a joint's motion: its equality constraints "
                         "do not depend on time, and an actuator is a force, not the law; the "
                         "driven joint '" +
                             joint.joint.name + "' is not mapped");
    }
  }
  (void)plan_joint_tree(scene, mujoco_joint_support());
}

JointSupport mujoco_joint_support() {
  JointSupport support;
  support.engine = "MuJoCo";
  support.as_tree = [](const constraint::IdealJointSpec& j) -> std::string {
    if (j.type == constraint::JointType::kDistance) {
      return "a distance joint leaves 5 degrees of freedom that no MuJoCo joint has";
    }
    return "";
  };
  support.as_loop = [](const constraint::IdealJointSpec& j) -> std::string {
    switch (j.type) {
      case constraint::JointType::kSpherical:
      case constraint::JointType::kRevolute:
      case constraint::JointType::kFixed:
      case constraint::JointType::kDistance:
        return "";
      default:
        return std::string("MuJoCo has no equality constraint for a ") +
               constraint::to_string(j.type) +
               " joint (connect, weld and a tendon's length only); make it a tree joint by "
               "closing the loop at another joint";
    }
  };
  return support;
}

std::string mujoco_integrator_name(const std::string& integrator) {
  if (integrator == "euler") return "Euler";
  if (integrator == "rk4") return "RK4";
  if (integrator == "implicit") return "implicit";
  if (integrator == "implicitfast") return "implicitfast";
  throw std::invalid_argument("unknown MuJoCo integrator '" + integrator + "'");
}

std::string scene_mjcf(const std::string& name, const RigidScene& scene, double dt,
                       const std::string& integrator, const ConstraintSoftness& softness) {
  std::ostringstream x;
  x << "<mujoco model=\"" << name << "\">\n";
  // Masses and inertias exactly as given: nothing inferred from geometry, no lower bounds.
  x << "  <compiler angle=\"radian\" inertiafromgeom=\"false\" boundmass=\"0\" "
       "boundinertia=\"0\" balanceinertia=\"false\"/>\n";
  x << "  <option timestep=\"" << number(dt) << "\" integrator=\""
    << mujoco_integrator_name(integrator) << "\" gravity=\"" << vector3(scene.g_W)
    << "\" density=\"0\" viscosity=\"0\" wind=\"0 0 0\">\n";
  x << "    <flag contact=\"disable\"/>\n";
  x << "  </option>\n";
  x << "  <worldbody>\n";
  MjcfWriter writer(scene, x);
  writer.sites_on(-1, "    ");
  // The bodies below the world: every body without ideal joints (in the scene's order), else the
  // roots and the ground's children in the tree's order, each with its subtree.
  if (scene.tree.empty()) {
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) writer.body(static_cast<int>(b), "    ");
  }
  for (int b : scene.tree_order) {
    if (scene.tree[static_cast<std::size_t>(b)].parent < 0) writer.body(b, "    ");
  }
  x << "  </worldbody>\n";
  const bool rods = [&] {
    for (int l : scene.loops) {
      if (scene.ideal_joints[static_cast<std::size_t>(l)].kind == IdealJointKind::kDistance) {
        return true;
      }
    }
    return false;
  }();
  if (!scene.springs.empty() || !scene.linear_springs.empty() || rods) {
    x << "  <tendon>\n";
    const auto tendon = [&](const std::string& element, const std::string& attributes) {
      x << "    <spatial name=\"" << element << "\"" << attributes << ">\n"
        << "      <site site=\"" << element << "_a\"/>\n"
        << "      <site site=\"" << element << "_b\"/>\n"
        << "    </spatial>\n";
    };
    for (std::size_t j = 0; j < scene.springs.size(); ++j) {
      tendon("joint" + std::to_string(j), " stiffness=\"" + number(scene.springs[j].stiffness) +
                                              "\" damping=\"0\" springlength=\"0\"");
    }
    for (std::size_t j = 0; j < scene.linear_springs.size(); ++j) {
      const LinearSpringInput& s = scene.linear_springs[j];
      tendon("spring" + std::to_string(j), " stiffness=\"" + number(s.stiffness) + "\" damping=\"" +
                                               number(s.damping) + "\" springlength=\"" +
                                               number(s.rest_length) + "\"");
    }
    for (int l : scene.loops) {
      if (scene.ideal_joints[static_cast<std::size_t>(l)].kind == IdealJointKind::kDistance) {
        tendon("rod" + std::to_string(l), "");
      }
    }
    x << "  </tendon>\n";
  }
  if (!scene.loops.empty()) {
    const double arm = joint_arm(scene);
    const std::string soft = " " + softness.attributes(dt);
    x << "  <equality>\n";
    for (int l : scene.loops) {
      const IdealJointInput& j = scene.ideal_joints[static_cast<std::size_t>(l)];
      const std::string& a = scene.bodies[static_cast<std::size_t>(j.a.body)].name;
      const std::string b =
          j.b.body < 0 ? std::string() : scene.bodies[static_cast<std::size_t>(j.b.body)].name;
      const std::string second = b.empty() ? "" : " body2=\"" + b + "\"";
      const auto connect = [&](const std::string& suffix, const Eigen::Vector3d& anchor) {
        x << "    <connect name=\"" << j.name << suffix << "\" body1=\"" << a << "\"" << second
          << " anchor=\"" << vector3(anchor) << "\"" << soft << "/>\n";
      };
      switch (j.kind) {
        case IdealJointKind::kSpherical:
          connect("", j.a.p_BoP_B);
          break;
        case IdealJointKind::kRevolute:
          connect("", j.a.p_BoP_B);
          connect("_axis", j.a.p_BoP_B + arm * j.a.R_BJ.col(2));
          break;
        case IdealJointKind::kFixed:
          x << "    <weld name=\"" << j.name << "\" body1=\"" << a << "\"" << second << soft
            << "/>\n";
          break;
        case IdealJointKind::kDistance:
          x << "    <tendon name=\"" << j.name << "\" tendon1=\"rod" << l << "\"" << soft << "/>\n";
          break;
        default:
          throw std::logic_error("joint kind without a MuJoCo equality");
      }
    }
    x << "  </equality>\n";
  }
  x << "</mujoco>\n";
  return x.str();
}

}  // namespace flexref::engines
