#pragma once
/// \file wear_depth_update.hpp
/// The contacts' worn depths in the fixed-step schemes (docs/wear.md, "Fully coupled
/// reference"): C1, C2, NMB and genalpha advance them beside the bodies by Heun's
/// predictor–corrector, the trapezoidal rule the schemes use for the wear work made explicit:
///   predictor  h̃_{n+1} = h_n + Δt ḣ_n                (the geometry of the step's loads)
///   corrector  h_{n+1} = h_n + ½ Δt (ḣ_n + ḣ(x_{n+1}, h̃_{n+1}))
/// Second order like the schemes (the loads see the depth to O(Δt²) within a step), and exact
/// for a constant wear rate. One more evaluation of the contacts per step, only when the model
/// has a wear law. A stepper calls start after (re)initializing, predict before its force
/// evaluation, correct once x_{n+1} is known and accept when the step is taken; a failed step
/// leaves the rates of t_n. Allocates nothing after construction.
#include <Eigen/Core>

#include "core/model.hpp"

namespace flexref::lie::detail {

class WearDepthUpdate {
 public:
  explicit WearDepthUpdate(const core::Model& model);

  /// True when the model has worn depths (the other calls do nothing otherwise).
  bool active() const { return rate_.size() > 0; }
  /// ḣ_n at the state.
  void start(const core::LoadContext& context, const core::State& state, core::Workspace& ws);
  /// next.wear_depth ← h_n + Δt ḣ_n.
  void predict(const core::State& state, double dt, core::State& next) const;
  /// ḣ_{n+1} at `next` (its predicted depths), then next.wear_depth ← h_n + ½ Δt (ḣ_n + ḣ_{n+1}).
  void correct(const core::LoadContext& context, const core::State& state, double dt,
               core::State& next, core::Workspace& ws);
  /// The step is taken: ḣ_{n+1} becomes ḣ_n.
  void accept() { rate_.swap(rate_next_); }

 private:
  const core::Model* model_;
  Eigen::VectorXd rate_;       ///< ḣ_n, m/s
  Eigen::VectorXd rate_next_;  ///< ḣ_{n+1}
};

}  // namespace flexref::lie::detail
