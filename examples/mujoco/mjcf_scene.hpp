#pragma once
/// \file mjcf_scene.hpp
/// A flexref scene as a MuJoCo model (MJCF text, docs/engines.md "MuJoCo"):
///
/// - a root body (one no ideal joint ties to the ground or to another body's tree):
///   `<freejoint/>` at the body frame origin Bo, placed at its initial position and attitude
///   (MuJoCo's quaternions are scalar first, body → world, as flexref's Euler parameters); a
///   pivot body: a ball joint at the pivot, placed at its initial pose (the ball's quaternion
///   starts at identity);
/// - ideal joints (docs/joints.md, "Ideal joints") on the tree of joint_tree.hpp: a body below its
///   parent, placed at its initial pose relative to the parent's (so that every joint coordinate
///   is 0 in the initial configuration, which core::Model made consistent with the joints), with
///   its tree joint at its end's point and axis: revolute → hinge, spherical → ball, prismatic →
///   slide, cylindrical → hinge and slide on one axis, universal → a hinge about the parent's
///   axis then one about the child's (MuJoCo composes a body's joints in order, the first fixed
///   in the parent, the last in the child), fixed → no joint (the body is welded to its parent);
/// - joints closing loops as equality constraints, held by MuJoCo's soft constraint solver with
///   the adapter's solref/solimp: spherical → connect (anchor on the first body; MuJoCo takes
///   the second body's point from the initial configuration), revolute → two connects, at the
///   joint point and at a point one arm ℓ along the axis (the second holds the axes parallel;
///   ℓ the largest distance of a joint point from its body's origin in the scene, 1 m when all
///   are 0), fixed → weld (the relative pose of the initial configuration), distance → a spatial
///   tendon between the two points whose length a tendon equality holds at its initial value
///   (the rod's length: core::Model assembled it). MuJoCo has no equality for a prismatic,
///   cylindrical or universal joint, nor a way to prescribe a joint's motion: such a loop and
///   every drive are refused;
/// - mass, centre of mass and the full inertia tensor about it (`fullinertia`), never inferred
///   from geometry: the model has no geoms at all, so nothing can collide, and contacts are
///   disabled besides;
/// - gravity, the timestep and the integrator as options; air density and viscosity zero;
/// - an undamped spherical bushing as a spatial tendon between two sites with the bushing's
///   stiffness and zero rest length (MuJoCo's tendon spring k·(L − 0) along the line is the
///   bushing's k·d); a [[spring]] as a spatial tendon with its stiffness, damping and rest
///   length (MuJoCo's tendon force −k (L − L0) − c L̇ along the line is flexref's);
/// - applied loads are not part of the MJCF: mujoco_engine.cpp applies them through
///   `mjcb_control` at every stage of every step.
///
/// What MuJoCo has no exact equivalent for is refused (MappingError naming the scene key):
/// penalty contacts (MuJoCo's contacts are soft constraints, solref/solimp, not flexref's
/// Hunt–Crossley or linear spring–dashpot), revolute and damped bushings, drives, and the loops
/// above.
#include <array>
#include <string>

#include "examples/engine_adapter/joint_tree.hpp"
#include "examples/engine_adapter/rigid_scene.hpp"
#include "scene/scene.hpp"

namespace flexref::engines {

/// The softness of MuJoCo's equality constraints (its `solref` and `solimp` attributes, MuJoCo
/// documentation "Solver parameters"): the constraint's acceleration is (1 − d) of the
/// unconstrained one plus d of a reference −b ṙ − k d r, with the impedance d from solimp
/// (dmin at zero violation, dmax beyond `width`) and k, b from solref: timeconst τ and
/// damping ratio ζ give b = 2/(dmax τ), k = 1/(dmax² τ² ζ²); negative values (−k, −b) give them
/// directly. MuJoCo raises τ to 2·timestep when it is smaller (its `refsafe` flag).
struct ConstraintSoftness {
  /// TIMECONST DAMPRATIO; TIMECONST 0 (the adapter's default) stands for 2 × the step, the
  /// stiffest constraint MuJoCo integrates (it raises a smaller time constant to that).
  std::array<double, 2> solref{0.0, 1.0};
  /// The adapter's default impedance is the largest MuJoCo allows (0.9999, its mjMAXIMP);
  /// MuJoCo's own default, 0.9 to 0.95, leaves 5–10 % of the unconstrained acceleration in
  /// the joint.
  std::array<double, 5> solimp{kMaxImpedance, kMaxImpedance, 0.001, 0.5, 2.0};
  static constexpr double kMaxImpedance = 0.9999;
  /// "solref=\"…\" solimp=\"…\"" at the step dt. With the default solref a joint stays off by
  /// about (1 − d)/d² × a / k per acceleration a that the constraint holds against (the
  /// reference acceleration's equilibrium) with k ∝ 1/τ² = 1/(2 dt)²: the violation shrinks
  /// as dt² instead of leaving a floor; a fixed TIMECONST leaves the floor docs/engines.md
  /// measures.
  std::string attributes(double dt) const;
};

/// Throws MappingError for the first part of the scene MuJoCo cannot carry exactly.
void check_mujoco_mappable(const scene::Scene& scene);

/// What MuJoCo carries of ideal joints (joint_tree.hpp): every kind but distance in the tree,
/// spherical, revolute, fixed and distance as loop closures, no drive.
JointSupport mujoco_joint_support();

/// MuJoCo's name of a flexref integrator name ("euler" → "Euler", "rk4" → "RK4", …).
std::string mujoco_integrator_name(const std::string& integrator);

/// The MJCF model of a scene that check_mujoco_mappable accepted (its plain data).
std::string scene_mjcf(const std::string& name, const RigidScene& scene, double dt,
                       const std::string& integrator, const ConstraintSoftness& softness);

}  // namespace flexref::engines
