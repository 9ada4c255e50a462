#pragma once
/// \file rigid_scene.hpp
/// A scene an engine can map, as plain data (Eigen and the standard library only, valid
/// C++17): the form an engine's own translation unit sees when the engine's headers cannot be
/// compiled as C++20 beside flexref's (Simbody 3.7's comparison operators are ambiguous under
/// C++20's rewritten candidates). scene_mapping.hpp builds it from a flexref scene.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace flexref::engines {

/// One body at one output time, in flexref's conventions (docs/output.md).
struct BodySample {
  Eigen::Vector3d p_WBo = Eigen::Vector3d::Zero();  ///< frame origin, world, m
  Eigen::Vector4d e_WB{1.0, 0.0, 0.0, 0.0};         ///< Euler parameters body→world, scalar first
  Eigen::Vector3d v_WBo = Eigen::Vector3d::Zero();  ///< velocity of the frame origin, world, m/s
  Eigen::Vector3d w_WB_B = Eigen::Vector3d::Zero();  ///< angular velocity, body frame, rad/s
};

/// The fixed-step run the adapter asks for: t_n = n·dt, n = 0 … step_count, and the steps
/// that land on the scene's output times and on its load switches (validated by
/// lie::validate_step_grid, so every one of them is a whole number of steps).
struct StepPlan {
  double dt = 0.0;
  long step_count = 0;
  std::vector<double> output_times;
  std::vector<long> output_steps;  ///< n with n·dt = output_times[k]
  std::vector<long> switch_steps;  ///< n with n·dt a load discontinuity in (0, end], ascending
  /// The time of step n, computed by multiplication, never accumulated.
  double time(long n) const { return static_cast<double>(n) * dt; }
};

/// Called at each output time k with every body's sample, in the scene's body order.
using Recorder =
    std::function<void(std::size_t k, double t_engine, const std::vector<BodySample>& bodies)>;

/// The pose of a body where its loads are evaluated.
struct LoadPose {
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();  ///< body → world
  Eigen::Vector3d p_WBo = Eigen::Vector3d::Zero();     ///< frame origin, world
};

/// Force and moment of the loads on one body, world frame.
struct LoadWrench {
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();  ///< resultant force, N
  Eigen::Vector3d m_W = Eigen::Vector3d::Zero();  ///< moment about the reference point, N·m
};

struct RigidBodyInput {
  std::string name;
  double mass = 1.0;
  Eigen::Vector3d p_BoBcm_B = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I_Bcm_B = Eigen::Matrix3d::Identity();  ///< about the centre of mass
  bool pivot = false;                                     ///< else free
  Eigen::Vector3d p_BoPivot_B = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_WBo = Eigen::Vector3d::Zero();  ///< initial state
  Eigen::Vector4d e_WB{1.0, 0.0, 0.0, 0.0};
  Eigen::Vector3d v_WBo = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_B = Eigen::Vector3d::Zero();
};

/// A frictionless Hunt–Crossley sphere on a fixed plane: F = k δ^1.5 (1 + α δ̇), F ≥ 0.
struct SpherePlaneInput {
  int body = 0;
  Eigen::Vector3d p_BoC_B = Eigen::Vector3d::Zero();
  double radius = 0.0;
  Eigen::Vector3d p_WQ = Eigen::Vector3d::Zero();  ///< a point of the plane
  Eigen::Vector3d n_W = Eigen::Vector3d::UnitZ();  ///< unit normal toward the free side
  double stiffness = 0.0;                          ///< k, N/m^1.5
  double alpha = 0.0;                              ///< α, s/m
};

/// An undamped spherical bushing: F = k·d between point_a of body_a and point_b of body_b
/// (body_b = −1: the world point point_b).
struct SpringInput {
  int body_a = 0;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  int body_b = -1;
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  double stiffness = 0.0;
};

/// A linear spring–damper with a rest length between two points ([[spring]],
/// contact/spring_damper.hpp): axial force (k (ℓ − ℓ0) + c ℓ̇) along the line of the points.
struct LinearSpringInput {
  int body_a = 0;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< body_a frame, from Bo
  int body_b = -1;                                    ///< −1: the ground
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< body_b frame, or world
  double stiffness = 0.0;                             ///< k, N/m
  double damping = 0.0;                               ///< c, N·s/m
  double rest_length = 0.0;                           ///< ℓ0, m
};

/// The kinds of ideal joint (constraint::JointType, docs/joints.md "Ideal joints").
enum class IdealJointKind {
  kSpherical,
  kRevolute,
  kPrismatic,
  kCylindrical,
  kUniversal,
  kFixed,
  kDistance
};

/// One end of an ideal joint: its body (−1: the ground), its point from Bo and its joint frame J
/// (columns x, y, z; z the joint axis), both in the body frame (ground: world). The two ends'
/// frames coincide in the assembled initial configuration.
struct JointEndInput {
  int body = -1;
  Eigen::Vector3d p_BoP_B = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_BJ = Eigen::Matrix3d::Identity();
};

/// A drive's law: the relative coordinate of the first body about (revolute, rad) or along
/// (prismatic, m) the axis from the initial configuration, and its first two derivatives.
struct DriveValue {
  double q = 0.0, qd = 0.0, qdd = 0.0;
};
using DriveLaw = std::function<DriveValue(double t)>;

/// An ideal joint as an engine maps it.
struct IdealJointInput {
  std::string name;
  IdealJointKind kind = IdealJointKind::kSpherical;
  JointEndInput a;  ///< the first end: always a body
  JointEndInput b;
  double length = 0.0;  ///< distance joints, m
  DriveLaw drive;       ///< empty: not driven
};

/// How a body hangs in the engine's tree of bodies: below its parent by a tree joint (the
/// engine's mobilizer), or a root (free, or the scene's pivot to the ground).
struct TreeLink {
  int parent = -1;         ///< the parent body, −1 the ground
  int joint = -1;          ///< the ideal joint that is the body's mobilizer; −1: a root
  bool child_is_a = true;  ///< the body is the joint's first end (else its second)
};

struct RigidScene {
  Eigen::Vector3d g_W = Eigen::Vector3d::Zero();
  std::vector<RigidBodyInput> bodies;
  std::vector<SpherePlaneInput> contacts;
  std::vector<SpringInput> springs;
  std::vector<LinearSpringInput> linear_springs;
  /// Ideal joints: tree[b] places body b (empty when the scene has no ideal joint, every body
  /// then a root); tree_order lists the bodies parents first; loops are the joints that close
  /// loops of the tree (constraints in the engine).
  std::vector<IdealJointInput> ideal_joints;
  std::vector<TreeLink> tree;
  std::vector<int> tree_order;
  std::vector<int> loops;
  bool has_loads = false;
  /// The loads on body b at time t, branch of piecewise profiles from t_segment, moment about
  /// the world point p_WR.
  std::function<LoadWrench(int b, double t, double t_segment, const LoadPose& pose,
                           const Eigen::Vector3d& p_WR)>
      loads;
};

}  // namespace flexref::engines
