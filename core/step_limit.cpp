#include "core/step_limit.hpp"

#include <span>

#include "core/body.hpp"

namespace flexref::core {

std::vector<PenaltyMode> penalty_modes(const Model& model) {
  std::vector<PenaltyMode> modes;
  std::vector<std::pair<std::string, int>> counts;
  const std::span<const Body> bodies(model.bodies());
  const auto elements = model.elements();
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const ForceElement& element = *elements[e];
    const std::size_t first = modes.size();
    element.append_penalty_modes(bodies, modes);
    if (modes.size() == first) continue;
    for (std::size_t i = first; i < modes.size(); ++i) modes[i].element = static_cast<int>(e);
    if (!element.label().empty()) {
      for (std::size_t i = first; i < modes.size(); ++i) {
        modes[i].label = element.label() + modes[i].label;
      }
      continue;
    }
    const std::string& kind = modes[first].kind;
    int number = 1;
    bool found = false;
    for (auto& [k, n] : counts) {
      if (k == kind) {
        number = ++n;
        found = true;
      }
    }
    if (!found) counts.emplace_back(kind, 1);
    for (std::size_t i = first; i < modes.size(); ++i) {
      modes[i].label = kind + "[" + std::to_string(number) + "]" + modes[i].label;
    }
  }
  return modes;
}

std::vector<PenaltyMode> stiff_modes(const Model& model) {
  std::vector<PenaltyMode> modes;
  for (const Body& b : model.bodies()) {
    const Eigen::VectorXd& w = b.natural_frequencies();
    if (!b.is_flexible() || w.size() == 0) continue;
    Eigen::Index k = 0;
    const double omega_max = w.maxCoeff(&k);
    if (!(omega_max > 0.0)) continue;
    PenaltyMode mode;
    mode.label = b.name();
    mode.kind = "flexible body";
    mode.stiffness = b.modal_stiffness()(k);
    mode.inertia = mode.stiffness / (omega_max * omega_max);
    mode.frequency = omega_max;
    mode.step_limit = 2.0 / omega_max;
    modes.push_back(mode);
  }
  for (PenaltyMode& m : penalty_modes(model)) modes.push_back(std::move(m));
  return modes;
}

StepLimit explicit_step_limit(const Model& model) {
  StepLimit limit;
  for (const PenaltyMode& m : stiff_modes(model)) {
    if (m.step_limit < limit.h) {
      limit.h = m.step_limit;
      limit.frequency = m.frequency;
      limit.what = m.kind == "flexible body" ? "flexible body " + m.label : m.label;
    }
  }
  return limit;
}

}  // namespace flexref::core
