#include "core/impact_counter.hpp"

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

void ImpactCounter::update(const LoadContext& context, const State& state, Workspace& ws) {
  if (gaps_.empty()) return;
  model_->switching_functions(context, state, ws, gaps_);
  const std::vector<int>& channels = model_->switching_channels();
  for (std::size_t k = 0; k < gaps_.size(); ++k) {
    const bool separated = gaps_[k] > 0.0;
    if (separated_[k] && !separated && channels[k] >= 0) {
      counts_[static_cast<std::size_t>(channels[k])] += 1.0;
    }
    separated_[k] = separated;
  }
}

}  // namespace flexref::core
