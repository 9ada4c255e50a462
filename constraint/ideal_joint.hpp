#pragma once
/// \file ideal_joint.hpp
/// An ideal (holonomic, massless, frictionless) joint as the scene describes it: its kind, its
/// two ends and, for a driven revolute or prismatic joint, the law of the relative coordinate
/// (docs/joints.md, "Ideal joints"; docs/design/model.md, "Ideal joints"). Plain double data;
/// constraint::IdealJointsTpl<S> evaluates the rows in any scalar type.
#include <Eigen/Core>
#include <string>

#include "core/prescribed_motion.hpp"

namespace flexref::constraint {

/// The second end of a joint on the ground (its point and axes are then world data).
inline constexpr int kGround = -1;

enum class JointType {
  kSpherical,    ///< points coincide: 3 rows
  kRevolute,     ///< spherical + the axes parallel: 5 rows (+1 driven)
  kPrismatic,    ///< no relative rotation, the points on the axis: 5 rows (+1 driven)
  kCylindrical,  ///< the axes parallel, the points on the axis: 4 rows
  kUniversal,    ///< spherical + the two axes perpendicular: 4 rows
  kFixed,        ///< no relative motion: 6 rows
  kDistance,     ///< a massless rod: |p_a − p_b| = L, 1 row
};

/// "spherical", "revolute", … (the scene's kind).
const char* to_string(JointType type);
/// Number of constraint rows of a joint of this type (driven: one more).
int row_count(JointType type, bool driven);

/// One end of a joint.
struct JointEnd {
  int body = kGround;
  /// The joint point from the body's frame origin Bo, body frame (ground: world point).
  Eigen::Vector3d p_BoP_B = Eigen::Vector3d::Zero();
  /// A flexible body's node whose position the end is (it moves by Φ_k q_f), −1 for a point of
  /// the rigid part (hub); phi_B holds Φ_k (3×n) for a node end.
  int node = -1;
  Eigen::Matrix3Xd phi_B;
  /// The joint frame J of this end in the body frame (ground: world): columns x, y, z; z is the
  /// joint axis. The two ends' frames coincide in the assembled initial configuration (their x
  /// axes are made parallel there), so that fixed, prismatic and driven rows start at zero.
  Eigen::Matrix3d R_BJ = Eigen::Matrix3d::Identity();
};

/// A driven revolute or prismatic joint: the relative angle of the first body about the axis,
/// or its displacement along it, measured from the initial configuration, follows the law
/// (core::AngleLaw: a constant rate or the Kane–Ryan–Banerjee spin-up; rad or m).
struct JointDrive {
  bool active = false;
  core::AngleLaw law;
  /// The relative coordinate at t = 0 the law adds to: a prismatic joint's initial Z_b · d (m);
  /// zero for a revolute joint, whose end frames are aligned in the initial configuration.
  double offset = 0.0;
};

struct IdealJointSpec {
  std::string name;
  JointType type = JointType::kSpherical;
  JointEnd a;           ///< the first end: always a body; reactions are reported on it
  JointEnd b;           ///< the second end: a body or the ground
  double length = 0.0;  ///< distance joints: L > 0 (m)
  JointDrive drive;
};

}  // namespace flexref::constraint
