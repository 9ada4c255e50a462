#pragma once
/// \file simbody_mapping.hpp
/// What of a flexref scene Simbody carries exactly (docs/engines.md, "Simbody"): free and
/// pivot rigid bodies, gravity, applied loads, frictionless Hunt–Crossley sphere–plane
/// contacts with exponent 1.5 (HuntCrossleyForce), undamped spherical bushings
/// (LinearBushing), springs (TwoPointLinearSpring and TwoPointLinearDamper) and every kind of
/// ideal joint (simbody_joints.hpp: mobilizers in the tree, constraints closing loops, drives
/// as prescribed motion of a mobilizer). Everything else is refused with the scene key and the
/// reason: a driven joint that would have to close a loop, friction
/// (Simbody's Hollars law is not flexref's tanh-regularized Coulomb law), the linear law, other
/// exponents, points (radius 0: no Hertz radius), sphere–sphere pairs and gap supports,
/// revolute and damped bushings.
#include "examples/engine_adapter/joint_tree.hpp"
#include "scene/scene.hpp"

namespace flexref::engines {

/// Throws MappingError for the first part of the scene Simbody cannot carry exactly.
void check_simbody_mappable(const scene::Scene& scene);

/// What Simbody carries of ideal joints (joint_tree.hpp): every kind but distance as a
/// mobilizer, every kind as a loop closure, drives only on mobilizers.
JointSupport simbody_joint_support();

}  // namespace flexref::engines
