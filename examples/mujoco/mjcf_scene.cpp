#include "examples/mujoco/mjcf_scene.hpp"

#include <cstdio>
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

}  // namespace

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
}

std::string mujoco_integrator_name(const std::string& integrator) {
  if (integrator == "euler") return "Euler";
  if (integrator == "rk4") return "RK4";
  if (integrator == "implicit") return "implicit";
  if (integrator == "implicitfast") return "implicitfast";
  throw std::invalid_argument("unknown MuJoCo integrator '" + integrator + "'");
}

std::string scene_mjcf(const scene::Scene& scene, double dt, const std::string& integrator) {
  const scene::SceneSpec& spec = scene.spec;
  std::ostringstream x;
  x << "<mujoco model=\"" << spec.name << "\">\n";
  // Masses and inertias exactly as given: nothing inferred from geometry, no lower bounds.
  x << "  <compiler angle=\"radian\" inertiafromgeom=\"false\" boundmass=\"0\" "
       "boundinertia=\"0\" balanceinertia=\"false\"/>\n";
  x << "  <option timestep=\"" << number(dt) << "\" integrator=\""
    << mujoco_integrator_name(integrator) << "\" gravity=\"" << vector3(spec.g_W)
    << "\" density=\"0\" viscosity=\"0\" wind=\"0 0 0\">\n";
  x << "    <flag contact=\"disable\"/>\n";
  x << "  </option>\n";
  x << "  <worldbody>\n";
  for (std::size_t j = 0; j < spec.joints.size(); ++j) {
    if (spec.joints[j].b.body == contact::kGround) {
      x << "    <site name=\"joint" << j << "_b\" pos=\"" << vector3(spec.joints[j].b.point)
        << "\"/>\n";
    }
  }
  for (std::size_t b = 0; b < spec.bodies.size(); ++b) {
    const core::RigidBodyDescription& d = spec.bodies[b].description;
    const auto& e = d.initial.theta_WB;
    const Eigen::Matrix3d& I = d.I_Bcm_B;
    x << "    <body name=\"" << d.name << "\" pos=\"" << vector3(d.initial.p_WBo) << "\" quat=\""
      << number(e[0]) << " " << number(e[1]) << " " << number(e[2]) << " " << number(e[3])
      << "\">\n";
    if (d.motion == core::MotionKind::kFree) {
      x << "      <freejoint name=\"" << d.name << "_free\"/>\n";
    } else {
      x << "      <joint name=\"" << d.name << "_pivot\" type=\"ball\" pos=\""
        << vector3(d.p_BoPivot_B) << "\" damping=\"0\" armature=\"0\" stiffness=\"0\"/>\n";
    }
    x << "      <inertial pos=\"" << vector3(d.p_BoBcm_B) << "\" mass=\"" << number(d.mass)
      << "\" fullinertia=\"" << number(I(0, 0)) << " " << number(I(1, 1)) << " " << number(I(2, 2))
      << " " << number(I(0, 1)) << " " << number(I(0, 2)) << " " << number(I(1, 2)) << "\"/>\n";
    for (std::size_t j = 0; j < spec.joints.size(); ++j) {
      const scene::JointSpec& joint = spec.joints[j];
      if (joint.a.body == static_cast<int>(b)) {
        x << "      <site name=\"joint" << j << "_a\" pos=\"" << vector3(joint.a.point) << "\"/>\n";
      }
      if (joint.b.body == static_cast<int>(b)) {
        x << "      <site name=\"joint" << j << "_b\" pos=\"" << vector3(joint.b.point) << "\"/>\n";
      }
    }
    x << "    </body>\n";
  }
  x << "  </worldbody>\n";
  if (!spec.joints.empty()) {
    x << "  <tendon>\n";
    for (std::size_t j = 0; j < spec.joints.size(); ++j) {
      x << "    <spatial name=\"joint" << j << "\" stiffness=\""
        << number(spec.joints[j].parameters.stiffness) << "\" damping=\"0\" springlength=\"0\">\n"
        << "      <site site=\"joint" << j << "_a\"/>\n"
        << "      <site site=\"joint" << j << "_b\"/>\n"
        << "    </spatial>\n";
    }
    x << "  </tendon>\n";
  }
  x << "</mujoco>\n";
  return x.str();
}

}  // namespace flexref::engines
