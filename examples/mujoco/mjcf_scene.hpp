#pragma once
/// \file mjcf_scene.hpp
/// A flexref scene as a MuJoCo model (MJCF text, docs/engines.md "MuJoCo"):
///
/// - a free body: `<freejoint/>` at the body frame origin Bo, the body placed at its initial
///   position and attitude (MuJoCo's quaternions are scalar first, body → world, as flexref's
///   Euler parameters); a pivot body: a ball joint at the pivot, the body placed at its initial
///   pose (the ball's quaternion starts at identity);
/// - mass, centre of mass and the full inertia tensor about it (`fullinertia`), never inferred
///   from geometry: the model has no geoms at all, so nothing can collide, and contacts are
///   disabled besides;
/// - gravity, the timestep and the integrator as options; air density and viscosity zero;
/// - an undamped spherical bushing as a spatial tendon between two sites with the bushing's
///   stiffness and zero rest length (MuJoCo's tendon spring k·(L − 0) along the line is the
///   bushing's k·d);
/// - applied loads are not part of the MJCF: mujoco_engine.cpp applies them through
///   `mjcb_control` at every stage of every step.
///
/// What MuJoCo has no exact equivalent for is refused (MappingError naming the scene key):
/// penalty contacts (MuJoCo's contacts are soft constraints, solref/solimp, not flexref's
/// Hunt–Crossley or linear spring–dashpot), revolute and damped bushings.
#include <string>

#include "scene/scene.hpp"

namespace flexref::engines {

/// Throws MappingError for the first part of the scene MuJoCo cannot carry exactly.
void check_mujoco_mappable(const scene::Scene& scene);

/// MuJoCo's name of a flexref integrator name ("euler" → "Euler", "rk4" → "RK4", …).
std::string mujoco_integrator_name(const std::string& integrator);

/// The MJCF model of a scene that check_mujoco_mappable accepted.
std::string scene_mjcf(const scene::Scene& scene, double dt, const std::string& integrator);

}  // namespace flexref::engines
