#include "examples/simbody/simbody_joints.hpp"

#include <Eigen/Geometry>
#include <stdexcept>

namespace flexref::engines {
namespace {

SimTK::Vec3 vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

SimTK::UnitVec3 unit(const Eigen::Vector3d& v) { return SimTK::UnitVec3(vec3(v)); }

SimTK::Rotation rotation(const Eigen::Matrix3d& R) {
  SimTK::Mat33 m;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) m(i, k) = R(i, k);
  }
  return SimTK::Rotation(m);  // re-orthonormalized: the joint frames are orthonormal already
}

SimTK::Transform transform(const Eigen::Matrix3d& R, const Eigen::Vector3d& p) {
  return SimTK::Transform(rotation(R), vec3(p));
}

/// A body's initial pose and velocity (the ground's: identity and rest).
struct Motion0 {
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WBo = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WBo = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_W = Eigen::Vector3d::Zero();
  /// The velocity of the body point at the world position p.
  Eigen::Vector3d velocity_at(const Eigen::Vector3d& p) const {
    return v_WBo + w_WB_W.cross(p - p_WBo);
  }
};

Motion0 initial_motion(const RigidScene& scene, int body) {
  Motion0 m;
  if (body < 0) return m;
  const RigidBodyInput& b = scene.bodies[static_cast<std::size_t>(body)];
  m.R_WB = Eigen::Quaterniond(b.e_WB[0], b.e_WB[1], b.e_WB[2], b.e_WB[3])
               .normalized()
               .toRotationMatrix();
  m.p_WBo = b.p_WBo;
  m.v_WBo = b.v_WBo;
  m.w_WB_W = m.R_WB * b.w_WB_B;
  return m;
}

/// The mobilizer frame F = M of body b's tree joint in the world, in the initial configuration
/// (simbody_joints.hpp: J of the parent's end, turned to the mobilizer's axes).
struct WorldFrame {
  Eigen::Matrix3d R_WF;
  Eigen::Vector3d p_WF;
};

WorldFrame mobilizer_frame(const RigidScene& scene, int b) {
  const TreeLink& link = scene.tree[static_cast<std::size_t>(b)];
  const IdealJointInput& j = scene.ideal_joints[static_cast<std::size_t>(link.joint)];
  const JointEndInput& parent = link.child_is_a ? j.b : j.a;
  const JointEndInput& child = link.child_is_a ? j.a : j.b;
  const Motion0 P = initial_motion(scene, parent.body);
  const Motion0 C = initial_motion(scene, child.body);
  const Eigen::Matrix3d R_WJ = P.R_WB * parent.R_BJ;
  WorldFrame f{R_WJ, P.p_WBo + P.R_WB * parent.p_BoP_B};
  if (j.kind == IdealJointKind::kPrismatic) {
    f.R_WF << R_WJ.col(2), R_WJ.col(0), R_WJ.col(1);  // x along the joint axis
  } else if (j.kind == IdealJointKind::kUniversal) {
    // x the parent's axis, y the child's (perpendicular in the assembled configuration).
    const Eigen::Vector3d x = R_WJ.col(2);
    Eigen::Vector3d y = C.R_WB * child.R_BJ.col(2);
    y = (y - y.dot(x) * x).normalized();
    f.R_WF << x, y, x.cross(y);
  }
  return f;
}

/// A driven tree joint's Motion: q(t) = sign · the law, at the position level.
class DriveMotion final : public SimTK::Motion::Custom::Implementation {
 public:
  DriveMotion(DriveLaw law, double sign) : law_(std::move(law)), sign_(sign) {}
  SimTK::Motion::Level getLevel(const SimTK::State&) const override {
    return SimTK::Motion::Position;
  }
  void calcPrescribedPosition(const SimTK::State& s, int nq, SimTK::Real* q) const override {
    check(nq);
    q[0] = sign_ * law_(s.getTime()).q;
  }
  void calcPrescribedPositionDot(const SimTK::State& s, int nq, SimTK::Real* qd) const override {
    check(nq);
    qd[0] = sign_ * law_(s.getTime()).qd;
  }
  void calcPrescribedPositionDotDot(const SimTK::State& s, int nq,
                                    SimTK::Real* qdd) const override {
    check(nq);
    qdd[0] = sign_ * law_(s.getTime()).qdd;
  }

 private:
  static void check(int nq) {
    if (nq != 1) throw std::logic_error("a drive prescribes one coordinate");
  }
  DriveLaw law_;
  double sign_;
};

}  // namespace

SimTK::MobilizedBody add_tree_body(SimTK::MobilizedBody& parent, const SimTK::Body::Rigid& info,
                                   const RigidScene& scene, int b) {
  const TreeLink& link = scene.tree[static_cast<std::size_t>(b)];
  const IdealJointInput& j = scene.ideal_joints[static_cast<std::size_t>(link.joint)];
  const WorldFrame f = mobilizer_frame(scene, b);
  const Motion0 P = initial_motion(scene, link.parent);
  const Motion0 C = initial_motion(scene, b);
  const SimTK::Transform X_PF =
      transform(P.R_WB.transpose() * f.R_WF, P.R_WB.transpose() * (f.p_WF - P.p_WBo));
  const SimTK::Transform X_BM =
      transform(C.R_WB.transpose() * f.R_WF, C.R_WB.transpose() * (f.p_WF - C.p_WBo));
  SimTK::MobilizedBody mobod;
  switch (j.kind) {
    case IdealJointKind::kRevolute:
      mobod = SimTK::MobilizedBody::Pin(parent, X_PF, info, X_BM);
      break;
    case IdealJointKind::kPrismatic:
      mobod = SimTK::MobilizedBody::Slider(parent, X_PF, info, X_BM);
      break;
    case IdealJointKind::kCylindrical:
      mobod = SimTK::MobilizedBody::Cylinder(parent, X_PF, info, X_BM);
      break;
    case IdealJointKind::kUniversal:
      mobod = SimTK::MobilizedBody::Universal(parent, X_PF, info, X_BM);
      break;
    case IdealJointKind::kSpherical:
      mobod = SimTK::MobilizedBody::Ball(parent, X_PF, info, X_BM);
      break;
    case IdealJointKind::kFixed:
      mobod = SimTK::MobilizedBody::Weld(parent, X_PF, info, X_BM);
      break;
    case IdealJointKind::kDistance:
      throw std::logic_error("a distance joint is never a mobilizer");
  }
  if (j.drive) {
    SimTK::Motion::Custom(mobod, new DriveMotion(j.drive, link.child_is_a ? 1.0 : -1.0));
  }
  return mobod;
}

void add_loop_closure(SimTK::SimbodyMatterSubsystem& matter,
                      std::vector<SimTK::MobilizedBody>& bodies, const RigidScene& scene,
                      int joint) {
  const IdealJointInput& j = scene.ideal_joints[static_cast<std::size_t>(joint)];
  if (j.drive) throw std::logic_error("a driven joint never closes a loop in Simbody");
  SimTK::MobilizedBody& A = bodies[static_cast<std::size_t>(j.a.body)];
  SimTK::MobilizedBody& B =
      j.b.body < 0 ? matter.updGround() : bodies[static_cast<std::size_t>(j.b.body)];
  const SimTK::Vec3 x_a = vec3(j.a.p_BoP_B), x_b = vec3(j.b.p_BoP_B);
  const Eigen::Matrix3d& R_a = j.a.R_BJ;
  const Eigen::Matrix3d& R_b = j.b.R_BJ;
  const auto axes_parallel = [&] {  // Z_b · X_a = Z_b · Y_a = 0
    SimTK::Constraint::ConstantAngle(B, unit(R_b.col(2)), A, unit(R_a.col(0)));
    SimTK::Constraint::ConstantAngle(B, unit(R_b.col(2)), A, unit(R_a.col(1)));
  };
  const auto point_on_axis = [&] {  // X_b · d = Y_b · d = 0
    SimTK::Constraint::PointOnLine(B, unit(R_b.col(2)), x_b, A, x_a);
  };
  switch (j.kind) {
    case IdealJointKind::kSpherical:
      SimTK::Constraint::Ball(B, x_b, A, x_a);
      break;
    case IdealJointKind::kRevolute:
      SimTK::Constraint::Ball(B, x_b, A, x_a);
      axes_parallel();
      break;
    case IdealJointKind::kUniversal:
      SimTK::Constraint::Ball(B, x_b, A, x_a);
      SimTK::Constraint::ConstantAngle(B, unit(R_b.col(2)), A, unit(R_a.col(2)));
      break;
    case IdealJointKind::kFixed:
      SimTK::Constraint::Weld(B, transform(R_b, j.b.p_BoP_B), A, transform(R_a, j.a.p_BoP_B));
      break;
    case IdealJointKind::kDistance:
      SimTK::Constraint::Rod(B, x_b, A, x_a, j.length);
      break;
    case IdealJointKind::kPrismatic:
      point_on_axis();
      SimTK::Constraint::ConstantOrientation(B, rotation(R_b), A, rotation(R_a));
      break;
    case IdealJointKind::kCylindrical:
      point_on_axis();
      axes_parallel();
      break;
  }
}

void set_tree_velocity(SimTK::State& state, const SimTK::MobilizedBody& mobod,
                       const RigidScene& scene, int b) {
  const TreeLink& link = scene.tree[static_cast<std::size_t>(b)];
  if (scene.ideal_joints[static_cast<std::size_t>(link.joint)].drive) return;  // prescribed
  const WorldFrame f = mobilizer_frame(scene, b);
  const Motion0 P = initial_motion(scene, link.parent);
  const Motion0 C = initial_motion(scene, b);
  // M's origin coincides with F's in the initial configuration: its velocity in F is the
  // difference of the two bodies' velocities there.
  const Eigen::Vector3d w_FM_W = C.w_WB_W - P.w_WB_W;
  const Eigen::Vector3d v_FM_W = C.velocity_at(f.p_WF) - P.velocity_at(f.p_WF);
  mobod.setUToFitVelocity(state, SimTK::SpatialVec(vec3(f.R_WF.transpose() * w_FM_W),
                                                   vec3(f.R_WF.transpose() * v_FM_W)));
}

}  // namespace flexref::engines
