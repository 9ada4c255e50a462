#pragma once
/// \file simbody_mapping.hpp
/// What of a flexref scene Simbody carries exactly (docs/engines.md, "Simbody"): free and
/// pivot rigid bodies, gravity, applied loads, frictionless Hunt–Crossley sphere–plane
/// contacts with exponent 1.5 (HuntCrossleyForce) and undamped spherical bushings
/// (LinearBushing). Everything else is refused with the scene key and the reason: friction
/// (Simbody's Hollars law is not flexref's tanh-regularized Coulomb law), the linear law, other
/// exponents, points (radius 0: no Hertz radius), sphere–sphere pairs and gap supports,
/// revolute and damped bushings.
#include "scene/scene.hpp"

namespace flexref::engines {

/// Throws MappingError for the first part of the scene Simbody cannot carry exactly.
void check_simbody_mappable(const scene::Scene& scene);

}  // namespace flexref::engines
