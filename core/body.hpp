#pragma once
/// \file body.hpp
/// A body as the user describes it (design/model.md, "Bodies and inertia invariants" and
/// "Rigid motion modes"), and the internal form the model integrates.
///
/// Frames and points (Drake monogram notation): W world (global, Galilean), B body frame with
/// origin Bo, Bcm centre of mass, Br the reference point the equations are written about:
/// Bcm for a free body (Newton–Euler uncoupled), the pivot for a pivot body. A flexible body
/// (modal coordinates) will add its inertia invariants here and keep Br = Bo.
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/euler_parameters.hpp"

namespace flexref::core {

enum class MotionKind {
  kFree,   ///< 6 DOF
  kPivot,  ///< a body point fixed in space (spherical joint to ground): 3 rotational DOF
};

/// A named material point whose trajectory is an output (and where loads may be applied).
struct TrackedPoint {
  std::string name;
  Eigen::Vector3d p_BoP_B;  ///< position from the frame origin, body frame
};

/// Initial state in the user's frame: origin Bo, attitude, origin velocity, angular velocity.
struct BodyInitialState {
  Eigen::Vector3d p_WBo = Eigen::Vector3d::Zero();
  EulerParameters theta_WB = identity_euler_parameters();
  Eigen::Vector3d v_WBo = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_B = Eigen::Vector3d::Zero();
};

/// A rigid body as described by a scene.
struct RigidBodyDescription {
  std::string name;
  double mass = 1.0;
  Eigen::Vector3d p_BoBcm_B = Eigen::Vector3d::Zero();    ///< centre of mass
  Eigen::Matrix3d I_Bcm_B = Eigen::Matrix3d::Identity();  ///< inertia about Bcm, body frame
  MotionKind motion = MotionKind::kFree;
  Eigen::Vector3d p_BoPivot_B = Eigen::Vector3d::Zero();  ///< pivot (motion = pivot only)
  BodyInitialState initial;
  std::vector<TrackedPoint> points;
};

/// Thrown by Body when finite input gives mass or inertia data that overflow once derived
/// (1/m, the inertia about the pivot or its inverse), so a reader can report it at the
/// inertia key instead of guessing from the message.
class InertiaRangeError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The body the model integrates: data about the reference point Br, computed once.
class Body {
 public:
  /// Validates (mass > 0, inertia symmetric positive definite with the triangle inequality,
  /// unit attitude) and throws std::invalid_argument naming the problem.
  explicit Body(RigidBodyDescription description);

  const std::string& name() const { return description_.name; }
  const RigidBodyDescription& description() const { return description_; }
  MotionKind motion() const { return description_.motion; }
  bool is_free() const { return description_.motion == MotionKind::kFree; }
  double mass() const { return description_.mass; }

  /// Br in the body frame (Bcm for free bodies, the pivot for pivot bodies).
  const Eigen::Vector3d& p_BoBr_B() const { return p_BoBr_B_; }
  /// Centre of mass relative to Br (zero for free bodies).
  const Eigen::Vector3d& p_BrBcm_B() const { return p_BrBcm_B_; }
  /// Inertia about Br, body frame, and its inverse.
  const Eigen::Matrix3d& I_Br_B() const { return I_Br_B_; }
  const Eigen::Matrix3d& I_Br_B_inverse() const { return I_Br_B_inverse_; }
  /// Position of a body point relative to Br, body frame.
  Eigen::Vector3d p_BrP_B(const Eigen::Vector3d& p_BoP_B) const { return p_BoP_B - p_BoBr_B_; }

 private:
  RigidBodyDescription description_;
  Eigen::Vector3d p_BoBr_B_;
  Eigen::Vector3d p_BrBcm_B_;
  Eigen::Matrix3d I_Br_B_;
  Eigen::Matrix3d I_Br_B_inverse_;
};

/// Parallel-axis theorem: inertia about a point displaced by d from the centre of mass,
/// I_P = I_cm + m (|d|² I − d dᵀ).
Eigen::Matrix3d shift_inertia_from_com(const Eigen::Matrix3d& I_cm, double mass,
                                       const Eigen::Vector3d& d);

/// Why an inertia tensor is not physical, or empty when it is: symmetric, positive definite
/// and satisfying the triangle inequalities J_i + J_j ≥ J_k on its principal values.
std::string inertia_problem(const Eigen::Matrix3d& inertia);

}  // namespace flexref::core
