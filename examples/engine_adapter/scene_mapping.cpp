#include "examples/engine_adapter/scene_mapping.hpp"

#include "contact/contact_laws.hpp"
#include "examples/engine_adapter/joint_tree.hpp"

namespace flexref::engines {

void check_rigid_scene(const scene::Scene& scene, const std::string& engine) {
  for (const scene::BodySpec& body : scene.spec.bodies) {
    const core::RigidBodyDescription& d = body.description;
    if (d.flexible) {
      throw MappingError(body.source, "body '" + d.name + "' is flexible (modal coordinates); " +
                                          engine +
                                          " has rigid bodies only, so it cannot be mapped");
    }
    if (d.motion == core::MotionKind::kPrescribed) {
      throw MappingError(body.source, "body '" + d.name + "' has prescribed motion, which " +
                                          engine + "'s adapter does not map");
    }
  }
  if (!scene.spec.potentials.empty()) {
    throw MappingError(
        scene.spec.potentials.front().source,
        "the point-charge potential has no force element in " + engine + "; it cannot be mapped");
  }
}

LoadWrench body_load_wrench(const scene::SceneSpec& spec, int body, double t, double t_segment,
                            const LoadPose& pose, const Eigen::Vector3d& p_WR) {
  LoadWrench wrench;
  for (const scene::LoadSpec& load : spec.loads) {
    if (load.body != body) continue;
    const double scale = load.profile.value(t, t_segment);
    const Eigen::Vector3d value_W =
        load.frame == core::LoadFrame::kBody ? Eigen::Vector3d(pose.R_WB * load.value) : load.value;
    if (load.torque) {
      wrench.m_W += scale * value_W;
    } else {
      const Eigen::Vector3d f_W = scale * value_W;
      const Eigen::Vector3d p_WP = pose.p_WBo + pose.R_WB * load.p_BoP_B;
      wrench.f_W += f_W;
      wrench.m_W += (p_WP - p_WR).cross(f_W);
    }
  }
  return wrench;
}

bool has_load_jumps(const scene::SceneSpec& spec) {
  for (const scene::LoadSpec& load : spec.loads) {
    if (load.profile.shape() == core::TimeProfile::Shape::kRectangularPulse) return true;
  }
  return false;
}

namespace {

IdealJointKind kind_of(constraint::JointType type) {
  switch (type) {
    case constraint::JointType::kSpherical:
      return IdealJointKind::kSpherical;
    case constraint::JointType::kRevolute:
      return IdealJointKind::kRevolute;
    case constraint::JointType::kPrismatic:
      return IdealJointKind::kPrismatic;
    case constraint::JointType::kCylindrical:
      return IdealJointKind::kCylindrical;
    case constraint::JointType::kUniversal:
      return IdealJointKind::kUniversal;
    case constraint::JointType::kFixed:
      return IdealJointKind::kFixed;
    case constraint::JointType::kDistance:
      return IdealJointKind::kDistance;
  }
  throw std::logic_error("unknown joint type");
}

JointEndInput end_of(const constraint::JointEnd& end) {
  return JointEndInput{end.body, end.p_BoP_B, end.R_BJ};
}

/// The ideal joints, their tree and the model's consistent initial state.
void add_ideal_joints(const scene::Scene& scene, const JointSupport& support, RigidScene& out) {
  const JointTree tree = plan_joint_tree(scene, support);
  out.tree = tree.links;
  out.tree_order = tree.order;
  out.loops = tree.loops;
  for (const constraint::IdealJointSpec& j : built_ideal_joints(scene)) {
    IdealJointInput joint;
    joint.name = j.name;
    joint.kind = kind_of(j.type);
    joint.a = end_of(j.a);
    joint.b = end_of(j.b);
    joint.length = j.length;
    if (j.drive.active) {
      // The relative coordinate from the initial configuration: the law itself (a prismatic
      // joint's offset is its initial Z_b · d, which the engine's initial pose already has).
      const core::AngleLaw law = j.drive.law;
      joint.drive = [law](double t) {
        return DriveValue{law.angle(t), law.angular_rate(t), law.angular_acceleration(t)};
      };
    }
    out.ideal_joints.push_back(std::move(joint));
  }
  const core::Model& model = *scene.model;
  const core::State state = model.initial_state();
  for (std::size_t i = 0; i < out.bodies.size(); ++i) {
    const core::BodyState& s = state[i];
    RigidBodyInput& b = out.bodies[i];
    b.p_WBo = model.p_WBo(static_cast<int>(i), s);
    b.e_WB = s.theta_WB;
    b.v_WBo = model.v_WBo(static_cast<int>(i), s);
    b.w_WB_B = s.w_WB_B;
  }
}

}  // namespace

RigidScene rigid_scene(const scene::Scene& scene, const JointSupport& support) {
  const scene::SceneSpec& spec = scene.spec;
  RigidScene out;
  out.g_W = spec.g_W;
  for (const scene::BodySpec& body : spec.bodies) {
    const core::RigidBodyDescription& d = body.description;
    RigidBodyInput b;
    b.name = d.name;
    b.mass = d.mass;
    b.p_BoBcm_B = d.p_BoBcm_B;
    b.I_Bcm_B = d.I_Bcm_B;
    b.pivot = d.motion == core::MotionKind::kPivot;
    b.p_BoPivot_B = d.p_BoPivot_B;
    b.p_WBo = d.initial.p_WBo;
    b.e_WB = Eigen::Vector4d(d.initial.theta_WB[0], d.initial.theta_WB[1], d.initial.theta_WB[2],
                             d.initial.theta_WB[3]);
    b.v_WBo = d.initial.v_WBo;
    b.w_WB_B = d.initial.w_WB_B;
    out.bodies.push_back(b);
  }
  for (const scene::ContactSpec& c : spec.contacts) {
    // The same law build_model makes (scene/build_model.cpp): restitution 0.5 when not given.
    const contact::NormalLaw law = contact::NormalLaw::hunt_crossley(
        c.law.stiffness, c.law.exponent, c.law.restitution.value_or(0.5), c.law.reference_speed);
    for (const contact::ContactPair& pair : c.pairs) {
      SpherePlaneInput contact;
      contact.body = pair.body_b;
      contact.p_BoC_B = pair.p_BoCb_B;
      contact.radius = pair.radius_b;
      contact.p_WQ = pair.p_WQ;
      contact.n_W = pair.n_W;
      contact.stiffness = law.stiffness();
      contact.alpha = law.alpha();
      out.contacts.push_back(contact);
    }
  }
  for (const scene::JointSpec& joint : spec.joints) {
    out.springs.push_back(SpringInput{joint.a.body, joint.a.point, joint.b.body, joint.b.point,
                                      joint.parameters.stiffness});
  }
  for (const scene::SpringSpec& sp : spec.springs) {
    out.linear_springs.push_back(LinearSpringInput{sp.body_a, sp.point_a, sp.body_b, sp.point_b,
                                                   sp.parameters.stiffness, sp.parameters.damping,
                                                   sp.parameters.rest_length});
  }
  if (!spec.ideal_joints.empty()) add_ideal_joints(scene, support, out);
  out.has_loads = !spec.loads.empty();
  out.loads = [&spec](int b, double t, double t_segment, const LoadPose& pose,
                      const Eigen::Vector3d& p_WR) {
    return body_load_wrench(spec, b, t, t_segment, pose, p_WR);
  };
  return out;
}

}  // namespace flexref::engines
