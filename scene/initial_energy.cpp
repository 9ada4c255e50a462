#include "scene/initial_energy.hpp"

#include <cmath>
#include <vector>

#include "scene/build_model.hpp"

namespace flexref::scene {
namespace {

/// Whether `a` names the scene's energy better than `b`: a non-finite value before any finite
/// one, then the larger magnitude.
bool dominates(double a, double b) {
  const bool a_bad = !std::isfinite(a);
  const bool b_bad = !std::isfinite(b);
  if (a_bad != b_bad) return a_bad;
  return !a_bad && std::abs(a) > std::abs(b);
}

}  // namespace

EnergyPart largest_initial_energy(const SceneSpec& spec, const core::Model& model) {
  EnergyPart largest;
  bool found = false;
  const auto consider = [&](const SpecSource& source, const std::string& key,
                            const std::string& what, double energy) {
    if (found && !dominates(energy, largest.energy)) return;
    largest = {source, key, what, energy};
    found = true;
  };
  const core::State initial = model.initial_state();
  for (int i = 0; i < model.num_bodies(); ++i) {
    const auto ui = static_cast<std::size_t>(i);
    const SpecSource& source = spec.bodies[ui].source;
    core::State moving = initial;
    core::State strained = initial;
    for (std::size_t j = 0; j < initial.size(); ++j) {
      if (j == ui) continue;
      moving[j].v_WBr.setZero();
      moving[j].w_WB_B.setZero();
      moving[j].qd_f.setZero();
      strained[j].q_f.setZero();
    }
    consider(source, "", "kinetic energy", model.kinetic_energy(moving));
    if (model.body(i).is_flexible()) {
      consider(source, "", "elastic energy", model.elastic_energy(strained));
    }
  }
  // Model::potential_energy poses the bodies in the workspace (ws.kinematics) for the elements.
  core::Workspace ws = model.make_workspace();
  const core::LoadContext context{0.0, 0.0};
  (void)model.potential_energy(context, initial, ws);
  const std::vector<SpecSource> sources = element_sources(spec);
  const auto elements = model.elements();
  for (std::size_t e = 0; e < elements.size() && e < sources.size(); ++e) {
    const bool gravity = sources[e].path == "scene";
    consider(sources[e], gravity ? "gravity" : "", "potential energy",
             elements[e]->potential_energy(context, ws.kinematics));
  }
  return largest;
}

}  // namespace flexref::scene
