#pragma once
/// \file body.hpp
/// A body as the user describes it (docs/design/model.md, "Bodies and inertia invariants" and
/// "Rigid motion modes"), and the internal form the model integrates.
///
/// Frames and points (Drake monogram notation): W world (global, Galilean), B body frame with
/// origin Bo, Bcm centre of mass, Br the reference point the equations are written about:
/// Bcm for a free body (Newton–Euler uncoupled), the pivot for a pivot body. A flexible body
/// (modal coordinates q_f) keeps these reference points, taken on the UNDEFORMED body (Br is the
/// undeformed centre of mass of a free flexible body, hub included), and a prescribed body has
/// Br = Bo on the rotation axis. Flexible bodies carry their inertia invariants about Br.
#include <Eigen/Core>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/prescribed_motion.hpp"
#include "flexible/mass_matrix_solve.hpp"
#include "flexible/modal_data.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::core {

enum class MotionKind {
  kFree,   ///< 6 DOF
  kPivot,  ///< a body point fixed in space (spherical joint to ground): 3 rotational DOF
  /// The frame rotates by a given law about a fixed world axis through Bo (fixed): 0 rigid
  /// DOF; only modal coordinates are integrated (prescribed_motion.hpp).
  kPrescribed,
};

/// A named material point whose trajectory is an output (and where loads may be applied).
struct TrackedPoint {
  std::string name;
  Eigen::Vector3d p_BoP_B;  ///< undeformed position from the frame origin, body frame
  /// Flexible bodies: the modal-data node this point is (it moves by Φ_k q_f), or −1 for a
  /// point of the rigid part (hub), which does not deform.
  int node = -1;
};

/// Initial state in the user's frame: origin Bo, attitude, origin velocity, angular velocity.
struct BodyInitialState {
  Eigen::Vector3d p_WBo = Eigen::Vector3d::Zero();
  rotation::EulerParameters theta_WB = rotation::identity_euler_parameters();
  Eigen::Vector3d v_WBo = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_B = Eigen::Vector3d::Zero();
};

/// The deformable part of a body (docs/design/model.md): modal data (nodes from the frame origin
/// Bo) and the initial modal coordinates.
struct FlexiblePart {
  flexible::ModalData modal;
  Eigen::VectorXd q0;   ///< initial q_f (empty: zero)
  Eigen::VectorXd qd0;  ///< initial q̇_f (empty: zero)
};

/// A body as described by a scene: its rigid part (the whole body when `flexible` is empty,
/// else the hub, whose mass may then be zero) and optionally a flexible part.
struct RigidBodyDescription {
  std::string name;
  double mass = 1.0;
  Eigen::Vector3d p_BoBcm_B = Eigen::Vector3d::Zero();    ///< centre of mass
  Eigen::Matrix3d I_Bcm_B = Eigen::Matrix3d::Identity();  ///< inertia about Bcm, body frame
  MotionKind motion = MotionKind::kFree;
  Eigen::Vector3d p_BoPivot_B = Eigen::Vector3d::Zero();  ///< pivot (motion = pivot only)
  PrescribedRotation prescribed;                          ///< motion = prescribed only
  BodyInitialState initial;
  std::vector<TrackedPoint> points;
  std::optional<FlexiblePart> flexible;
};

/// Thrown by Body when finite input gives mass or inertia data that overflow once derived
/// (1/m, the inertia about the pivot or its inverse), so a reader can report it at the
/// inertia key instead of guessing from the message.
class InertiaRangeError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The body the model integrates: data about the reference point Br, computed once, in the
/// model's scalar type S (double; long double and float128 for the precision references). The
/// description is the scene's, in double; everything derived from it — Br, the inertia about
/// it and its inverse, a flexible body's invariants, modal damping and m_ff's factor, the
/// prescribed axis and the initial attitude as unit vectors — is formed in S, so a model in S
/// solves the exact model of the scene's numbers (docs/precision.md).
template <typename S>
class BodyTpl {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using Quaternion = Eigen::Matrix<S, 4, 1>;

  /// Validates (mass > 0, inertia symmetric positive definite with the triangle inequality,
  /// unit attitude; a flexible body: valid modal data, a hub mass ≥ 0 with a physical or zero
  /// inertia, and a positive definite undeformed inertia unless prescribed) and throws
  /// std::invalid_argument naming the problem.
  explicit BodyTpl(RigidBodyDescription description);

  const std::string& name() const { return description_.name; }
  const RigidBodyDescription& description() const { return description_; }
  MotionKind motion() const { return description_.motion; }
  bool is_free() const { return description_.motion == MotionKind::kFree; }
  bool is_prescribed() const { return description_.motion == MotionKind::kPrescribed; }
  bool is_flexible() const { return description_.flexible.has_value(); }
  /// Number of modal coordinates n (0 for a rigid body).
  int mode_count() const { return mode_count_; }
  /// Total mass (hub and nodes for a flexible body).
  const S& mass() const { return mass_; }

  /// Br in the body frame (Bcm for free bodies, the pivot for pivot bodies).
  const Vector3& p_BoBr_B() const { return p_BoBr_B_; }
  /// Centre of mass relative to Br (zero for free bodies).
  const Vector3& p_BrBcm_B() const { return p_BrBcm_B_; }
  /// Inertia about Br, body frame (undeformed for a flexible body, hub included), and its
  /// inverse (not formed for a prescribed body, whose inertia may be singular).
  const Matrix3& I_Br_B() const { return I_Br_B_; }
  const Matrix3& I_Br_B_inverse() const { return I_Br_B_inverse_; }
  /// Position of a body point relative to Br, body frame.
  Vector3 p_BrP_B(const Eigen::Vector3d& p_BoP_B) const {
    return p_BoP_B.template cast<S>() - p_BoBr_B_;
  }
  /// Position of a tracked point relative to Br, body frame, deformed by q_f when it is a node:
  /// ū_P = x_P + Φ_P q_f (eq. 10).
  Vector3 p_BrP_B(const TrackedPoint& point, const Vector& q_f) const;
  /// A prescribed body's axis (world) and every body's initial attitude, unit in S.
  const Vector3& axis_W() const { return axis_W_; }
  const Quaternion& theta_WB0() const { return theta_WB0_; }

  /// Flexible bodies: invariants about Br (nodes and hub), modal stiffness K_i and damping
  /// d_i = 2ζ_iω_iμ_i (diagonals), natural frequencies with the frame fixed (rad/s, ascending,
  /// in double: for step advice and `flexref check`).
  const flexible::ModalInvariantsTpl<S>& invariants() const { return invariants_; }
  const Vector& modal_stiffness() const { return stiffness_; }
  const Vector& modal_damping() const { return damping_; }
  const Eigen::VectorXd& natural_frequencies() const { return frequencies_; }
  /// The constant modal mass matrix m_ff factored once (Cholesky, and L⁻¹ Sᵀ) for the
  /// structured solves of flexible/mass_matrix_solve.hpp.
  const flexible::ModalMassFactorTpl<S>& modal_mass() const { return modal_mass_; }

 private:
  RigidBodyDescription description_;
  S mass_ = S(0);
  int mode_count_ = 0;
  flexible::ModalInvariantsTpl<S> invariants_;
  Vector stiffness_;
  Vector damping_;
  Eigen::VectorXd frequencies_;
  flexible::ModalMassFactorTpl<S> modal_mass_;
  Vector3 p_BoBr_B_;
  Vector3 p_BrBcm_B_;
  Matrix3 I_Br_B_;
  Matrix3 I_Br_B_inverse_;
  Vector3 axis_W_;
  Quaternion theta_WB0_;
};

using Body = BodyTpl<double>;
extern template class BodyTpl<double>;

/// Validates a description (what BodyTpl's constructor promises), in double whatever the model's
/// scalar type.
void validate_body_description(const RigidBodyDescription& description);

/// Parallel-axis theorem: inertia about a point displaced by d from the centre of mass,
/// I_P = I_cm + m (|d|² I − d dᵀ).
template <typename S>
Eigen::Matrix<S, 3, 3> shift_inertia_from_com(const Eigen::Matrix<S, 3, 3>& I_cm, const S& mass,
                                              const Eigen::Matrix<S, 3, 1>& d) {
  return I_cm + mass * (d.squaredNorm() * Eigen::Matrix<S, 3, 3>::Identity() - d * d.transpose());
}

/// Why an inertia tensor is not physical, or empty when it is: symmetric, positive definite
/// and satisfying the triangle inequalities J_i + J_j ≥ J_k on its principal values.
std::string inertia_problem(const Eigen::Matrix3d& inertia);

}  // namespace flexref::core
