#include "lie/wear_depth_update.hpp"

#include <cstddef>
#include <span>

namespace flexref::lie::detail {

WearDepthUpdate::WearDepthUpdate(const core::Model& model)
    : model_(&model),
      rate_(Eigen::VectorXd::Zero(model.wear_depth_count())),
      rate_next_(Eigen::VectorXd::Zero(model.wear_depth_count())) {}

void WearDepthUpdate::start(const core::LoadContext& context, const core::State& state,
                            core::Workspace& ws) {
  if (!active()) return;
  model_->wear_depth_rates(context, state, ws,
                           std::span<double>(rate_.data(), static_cast<std::size_t>(rate_.size())));
}

void WearDepthUpdate::predict(const core::State& state, double dt, core::State& next) const {
  if (!active()) return;
  // h̃_{n+1} ← h_n + Δt ḣ_n
  next.wear_depth = state.wear_depth + dt * rate_;
}

void WearDepthUpdate::correct(const core::LoadContext& context, const core::State& state, double dt,
                              core::State& next, core::Workspace& ws) {
  if (!active()) return;
  model_->wear_depth_rates(
      context, next, ws,
      std::span<double>(rate_next_.data(), static_cast<std::size_t>(rate_next_.size())));
  // h_{n+1} ← h_n + ½ Δt (ḣ_n + ḣ_{n+1})
  next.wear_depth = state.wear_depth + (0.5 * dt) * (rate_ + rate_next_);
}

}  // namespace flexref::lie::detail
