#include "examples/simbody/simbody_mapping.hpp"

#include "examples/engine_adapter/engine.hpp"
#include "examples/engine_adapter/scene_mapping.hpp"

namespace flexref::engines {

void check_simbody_mappable(const scene::Scene& scene) {
  check_rigid_scene(scene, "Simbody");
  for (const scene::ContactSpec& c : scene.spec.contacts) {
    const auto refuse = [&](const std::string& why) { throw MappingError(c.source, why); };
    if (c.gap) refuse("a gap support has no Simbody contact geometry; it is not mapped");
    if (c.law.linear) {
      refuse(
          "the linear spring-dashpot law has no Simbody contact force (HuntCrossleyForce is "
          "Hertzian); only Hunt-Crossley with exponent 1.5 is mapped");
    }
    if (c.law.exponent != 1.5) {
      refuse("Simbody's HuntCrossleyForce has the Hertz exponent 1.5 only; this contact has " +
             std::to_string(c.law.exponent));
    }
    if (c.friction.mu != 0.0) {
      refuse(
          "Simbody's friction (Hollars: static, dynamic, viscous, transition velocity) is not "
          "flexref's tanh-regularized Coulomb law; only frictionless contacts are mapped");
    }
    for (const contact::ContactPair& pair : c.pairs) {
      if (pair.kind != contact::ContactPair::Kind::kSpherePlane) {
        refuse("only sphere-plane contacts are mapped to Simbody");
      }
      if (!(pair.radius_b > 0.0)) {
        refuse("a point contact (radius 0) has no Hertz radius for Simbody's HuntCrossleyForce");
      }
    }
  }
  for (const scene::JointSpec& joint : scene.spec.joints) {
    if (joint.revolute) {
      throw MappingError(joint.source,
                         "a revolute bushing's angular spring k_theta (1 - cos alpha) has no "
                         "Simbody force element; only undamped spherical bushings are mapped");
    }
    if (joint.parameters.damping != 0.0) {
      throw MappingError(joint.source,
                         "a damped spherical bushing damps the inertial relative velocity; "
                         "Simbody's LinearBushing damps the rate seen in its frame F, so only "
                         "damping = 0 is mapped");
    }
  }
  (void)plan_joint_tree(scene, simbody_joint_support());
}

JointSupport simbody_joint_support() {
  JointSupport support;
  support.engine = "Simbody";
  support.as_tree = [](const constraint::IdealJointSpec& j) -> std::string {
    if (j.type == constraint::JointType::kDistance) {
      return "a distance joint leaves 5 degrees of freedom that no Simbody mobilizer has";
    }
    return "";
  };
  support.as_loop = [](const constraint::IdealJointSpec& j) -> std::string {
    if (j.drive.active) {
      return "a drive is a Simbody Motion, which prescribes a mobilizer's coordinate; this "
             "driven joint cannot be a mobilizer of the tree (its two bodies are joined "
             "already by other driven or tree-only joints)";
    }
    return "";
  };
  return support;
}

}  // namespace flexref::engines
