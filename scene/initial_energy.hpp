#pragma once
/// \file initial_energy.hpp
/// Which part of a scene holds its initial energy, so that a scene whose energy is not finite,
/// or beyond what the equations can carry, is reported at the key to change (the body whose
/// spin, velocity or centre of mass makes it, the potential whose alpha makes it) instead of
/// at the whole scene.
#include <string>

#include "core/model.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::scene {

struct EnergyPart {
  SpecSource source;    ///< the table ("body[2]", "potential[1]"; path "scene" for gravity)
  std::string key;      ///< the key in it ("gravity"), "" for the whole table
  std::string what;     ///< "kinetic energy", "elastic energy" or "potential energy"
  double energy = 0.0;  ///< J; may be infinite or NaN
};

/// At the model's initial state: each body's kinetic energy (the state with only that body
/// moving) and elastic energy (only its modal coordinates), and each force element's potential
/// energy (element_sources gives their tables). Returns the part whose energy is not finite, or
/// else the largest in magnitude; a scene with neither bodies nor elements gives an empty part.
EnergyPart largest_initial_energy(const SceneSpec& spec, const core::Model& model);

}  // namespace flexref::scene
