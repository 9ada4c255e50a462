/// \file model_integrals.cpp
/// The model's wear channels and the integrals the integrators track with the state
/// (docs/output.md): W_d, the applied work W_a of loads that keep doing work, and each
/// contact's wear work ∫ |F_t·v_t| dt.
#include <cstddef>

#include "core/model.hpp"

namespace flexref::core {

void Model::wear_samples(const LoadContext& context, const State& state, Workspace& ws) const {
  pose_bodies(state, ws);
  for (std::size_t c = 0; c < wear_elements_.size(); ++c) {
    const ForceElement& element = *elements_[static_cast<std::size_t>(wear_elements_[c])];
    element.wear_samples(context, ws.kinematics, std::span<WearSample>(&ws.wear[c], 1));
  }
}

void Model::integral_rates(const LoadContext& context, const State& state, Workspace& ws,
                           std::span<double> rates) const {
  rates[0] = dissipated_power(context, state, ws);  // poses the bodies
  std::size_t k = 1;
  if (!dissipates_) return;
  if (applied_work_) {
    double p = 0.0;
    for (const auto& e : elements_) p += e->applied_power(context, ws.kinematics);
    rates[k++] = p;
  }
  if (wear_elements_.empty()) return;
  for (std::size_t c = 0; c < wear_elements_.size(); ++c) {
    const ForceElement& element = *elements_[static_cast<std::size_t>(wear_elements_[c])];
    element.wear_samples(context, ws.kinematics, std::span<WearSample>(&ws.wear[c], 1));
    rates[k++] = ws.wear[c].wear_power;
  }
}

}  // namespace flexref::core
