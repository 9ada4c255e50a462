#pragma once
/// \file simbody_joints.hpp
/// A RigidScene's ideal joints as Simbody's mobilizers, constraints and motions
/// (docs/engines.md, "Simbody"; compiled as C++17 with simbody_system.cpp).
///
/// Tree joints (joint_tree.hpp) are mobilizers whose frames F (on the parent) and M (on the
/// child) coincide in the initial configuration, so that every mobilizer starts at q = 0 (a
/// Ball's q the identity quaternion): both frames are the joint frame J of the parent's end
/// placed in the world by the initial state (core::Model made it consistent with the joints)
/// and seen from either body. Simbody's mobilizers move about common axes of F and M, so J is
/// turned to their conventions: revolute → Pin (rotation about z), prismatic → Slider
/// (translation along x: F's x is J's z), cylindrical → Cylinder (about and along z),
/// universal → Universal (rotation about F's x, then about M's new y: F's x is the parent's
/// axis, its y the child's), spherical → Ball, fixed → Weld.
///
/// A driven tree joint is prescribed at the position level (Motion::Custom): q(t) is the drive
/// law itself, q̇ and q̈ its derivatives, signed by which end is the child (the law is the
/// first body's coordinate relative to the second's).
///
/// Loop closures are constraints holding flexref's own rows: spherical → Constraint::Ball,
/// revolute → Ball + two ConstantAngle (Z_b ⟂ X_a, Z_b ⟂ Y_a: the axes parallel), universal →
/// Ball + ConstantAngle (Z_b ⟂ Z_a), fixed → Constraint::Weld of the two joint frames,
/// distance → Constraint::Rod, prismatic → PointOnLine (the point on b's axis) +
/// ConstantOrientation (the two joint frames keep their relative attitude), cylindrical →
/// PointOnLine + two ConstantAngle. A driven loop closure is refused before (Simbody's Motion
/// acts on a mobilizer).
#include <Simbody.h>

#include <vector>

#include "examples/engine_adapter/rigid_scene.hpp"

namespace flexref::engines {

/// The mobilized body of scene body b below `parent` by its tree joint (scene.tree[b].joint ≥ 0),
/// with the joint's drive as a Motion.
SimTK::MobilizedBody add_tree_body(SimTK::MobilizedBody& parent, const SimTK::Body::Rigid& info,
                                   const RigidScene& scene, int b);

/// Loop joint `joint` as constraints between the mobilized bodies (−1: ground).
void add_loop_closure(SimTK::SimbodyMatterSubsystem& matter,
                      std::vector<SimTK::MobilizedBody>& bodies, const RigidScene& scene,
                      int joint);

/// Sets the u's of tree body b's mobilizer to the bodies' initial velocities (the mobilizer's
/// cross velocity V_FM in F from the parent's and the child's world velocities at the joint
/// point).
void set_tree_velocity(SimTK::State& state, const SimTK::MobilizedBody& mobod,
                       const RigidScene& scene, int b);

}  // namespace flexref::engines
