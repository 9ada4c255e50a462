#include "core/impact_counter.hpp"

#include <cmath>
#include <cstddef>

namespace flexref::core {

ImpactCounter::ImpactCounter(const Model& model)
    : model_(&model),
      gaps_(static_cast<std::size_t>(model.switching_function_count()), 0.0),
      separated_(gaps_.size(), true),
      counts_(static_cast<std::size_t>(model.wear_channel_count()), 0.0) {}

void ImpactCounter::start(const LoadContext& context, const State& state, Workspace& ws) {
  model_->switching_functions(context, state, ws, gaps_);
  for (std::size_t k = 0; k < gaps_.size(); ++k) separated_[k] = gaps_[k] > 0.0;
  for (double& c : counts_) c = 0.0;
}

void ImpactCounter::count(std::size_t k, bool separated) {
  const int channel = model_->switching_channels()[k];
  if (separated_[k] && !separated && channel >= 0)
    counts_[static_cast<std::size_t>(channel)] += 1.0;
  separated_[k] = separated;
}

void ImpactCounter::update(const LoadContext& context, const State& state, Workspace& ws) {
  if (gaps_.empty()) return;
  model_->switching_functions(context, state, ws, gaps_);
  for (std::size_t k = 0; k < gaps_.size(); ++k) count(k, gaps_[k] > 0.0);
}

void ImpactCounter::update_at_root(const LoadContext& context, const State& state, Workspace& ws) {
  if (gaps_.empty()) return;
  model_->switching_functions(context, state, ws, gaps_);
  bool changed = false;
  std::size_t nearest = 0;
  for (std::size_t k = 0; k < gaps_.size(); ++k) {
    changed = changed || (gaps_[k] > 0.0) != separated_[k];
    if (std::abs(gaps_[k]) < std::abs(gaps_[nearest])) nearest = k;
  }
  if (!changed) {
    count(nearest, !separated_[nearest]);
    return;
  }
  for (std::size_t k = 0; k < gaps_.size(); ++k) count(k, gaps_[k] > 0.0);
}

}  // namespace flexref::core
