#pragma once
/// \file mobilizer.hpp
/// One edge of a spanning tree of the ideal joints (docs/reduced_coordinates.md): the joint
/// coordinates q and velocities u that place a child body relative to its parent (or the
/// ground), Simbody's "mobilizer". Frames: F fixed in the parent (P), M fixed in the child (C);
/// the mobilizer gives the pose of M in F, X_FM(q) = (R_FM, p_FM), and its rate in F,
///   w_FM_F = H_w(q) u,   ṗ_FM (the derivative of p_FM expressed in F) = H_v(q) u,
/// with the parts of their derivatives that do not involve u̇ (the bias, "Ḣ u"). For a joint of
/// the tree, F and M are the joint frames J of its two ends (constraint/ideal_joint.hpp: z the
/// axis, the frames coinciding in the assembled configuration), so that every X_FM(q) satisfies
/// the joint's rows of constraint/ideal_joints.hpp exactly:
// clang-format off
///   kind         q                      u                 X_FM(q)
///   revolute     angle ψ about z        ψ̇                 (R_z(ψ), 0)
///   prismatic    slide s along z        ṡ                 (1, s z)
///   cylindrical  (ψ, s)                 (ψ̇, ṡ)            (R_z(ψ), s z)
///   universal    (ψ1, ψ2)               (ψ̇1, ψ̇2)          (R_z(ψ1) C R_z(ψ2), 0), C z ⊥ z
///   spherical    Euler parameters θ_FM  ω̄ = w_FM_M        (A(θ_FM), 0)
///   fixed        —                      —                 (1, 0)
///   pivot root   θ_WB                   ω̄ = w_WB_B        (A(θ), 0), F at the pivot, M = B
///   free root    (p_WBr, θ_WB)          (v_WBr, ω̄)        (A(θ), p_WBr), F = W, M = B at Br
// clang-format on
/// A universal joint's rows ask only that the two axes stay perpendicular (Z_b·Z_a = 0); C is
/// the assembled configuration's R_FM with C z made exactly perpendicular to z, so R_FM z =
/// R_z(ψ1) C z stays perpendicular to z for every (ψ1, ψ2). The spherical, pivot and free
/// coordinates carry Euler parameters whose rate is θ̇ = ½ θ ⊗ (0, ω̄), as the bodies' in the
/// maximal state (rotation/euler_parameters.hpp); the other coordinates have q̇ = u.
#include <Eigen/Core>
#include <string>

#include "constraint/ideal_joint.hpp"

namespace flexref::constraint {

enum class MobilizerKind {
  kFree,         ///< a root body without a tree joint: 7 q, 6 u
  kPivot,        ///< a root body on its pivot (core::MotionKind::kPivot): 4 q, 3 u
  kRevolute,     ///< 1 q, 1 u
  kPrismatic,    ///< 1 q, 1 u
  kCylindrical,  ///< 2 q, 2 u
  kUniversal,    ///< 2 q, 2 u
  kSpherical,    ///< 4 q, 3 u
  kFixed,        ///< 0 q, 0 u
};

const char* to_string(MobilizerKind kind);
int position_count(MobilizerKind kind);
int velocity_count(MobilizerKind kind);

/// H_w, H_v: 3 × (at most 6) without heap storage.
using MobilizerMap = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 6>;

struct Mobilizer {
  MobilizerKind kind = MobilizerKind::kFree;
  int joint = -1;        ///< the ideal joint it stands for (−1: a free or pivot root)
  int parent = kGround;  ///< the parent body (kGround: the world)
  int child = 0;
  /// F in the parent: its axes and origin from the parent's Br, parent frame (ground: world).
  Eigen::Matrix3d R_PF = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_PrF_P = Eigen::Vector3d::Zero();
  /// M in the child: its axes and origin from the child's Br, child frame.
  Eigen::Matrix3d R_CM = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_CrM_C = Eigen::Vector3d::Zero();
  /// Universal joints: R_FM at ψ1 = ψ2 = 0 (C z ⊥ z).
  Eigen::Matrix3d C = Eigen::Matrix3d::Identity();
  int q_offset = 0;  ///< where its q and u sit in the stacked coordinates
  int u_offset = 0;
};

/// X_FM, its rate maps and bias at (q, u) of one mobilizer (q, u: its own coordinates).
struct RelativeMotion {
  Eigen::Matrix3d R_FM = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_FM_F = Eigen::Vector3d::Zero();
  MobilizerMap H_w;  ///< w_FM_F = H_w u
  MobilizerMap H_v;  ///< ṗ_FM (in F) = H_v u
  /// dw_FM_F/dt and d²p_FM/dt² (in F) at u̇ = 0: Ḣ_w u and Ḣ_v u.
  Eigen::Vector3d w_dot_bias_F = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_ddot_bias_F = Eigen::Vector3d::Zero();
};

/// X_FM(q), H(q) and the bias at (q, u). Allocates nothing.
void relative_motion(const Mobilizer& m, const double* q, const double* u, RelativeMotion& out);

/// q ⊕ h u: the coordinates reached from q in time h at constant u (q + h u; Euler parameters
/// θ ⊗ exp(h ω̄), the exact flow of θ̇ = ½ θ ⊗ (0, ω̄) at constant ω̄). Writes q_out (may alias
/// q). Allocates nothing.
void advance_coordinates(const Mobilizer& m, const double* q, const double* u, double h,
                         double* q_out);

/// q̇ at (q, u): u, or for Euler parameters ½ θ̂ ⊗ (0, ω̄) with θ̂ = θ/|θ| (tangent to the sphere
/// through θ, so the exact flow keeps |θ|; as the maximal ODE form's, reference/ode_form.hpp).
/// Allocates nothing.
void coordinate_rates(const Mobilizer& m, const double* q, const double* u, double* q_dot);

/// Scales the mobilizer's Euler parameters (if any) to unit norm. Allocates nothing.
void normalize_coordinates(const Mobilizer& m, double* q);

/// The coordinates of a relative pose and motion: the inverse of relative_motion on its image
/// (angles in (−π, π]; Euler parameters with e0 ≥ 0 unless `theta` is given, which a root's
/// q takes as is). w_FM_F and p_dot_FM_F: the relative angular velocity and ṗ_FM in F.
void mobilizer_coordinates(const Mobilizer& m, const Eigen::Matrix3d& R_FM,
                           const Eigen::Vector3d& p_FM_F, const Eigen::Vector3d& w_FM_F,
                           const Eigen::Vector3d& p_dot_FM_F, const Eigen::Vector4d* theta,
                           double* q, double* u);

}  // namespace flexref::constraint
