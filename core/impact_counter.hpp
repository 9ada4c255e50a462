#pragma once
/// \file impact_counter.hpp
/// Counts the impacts of every wear channel (docs/output.md, `C.impacts`): an impact is an
/// onset, a switching function of the channel going from a positive gap (separated) to a gap
/// ≤ 0 (touching or penetrating) between two states an integrator accepted. References call
/// update() at every located root — the root finders return the state just past the sign
/// change — and at every output; schemes call it after every step, whose size resolves the
/// contact (an impact that opens and closes inside one step is not seen by any integrator).
#include <vector>

#include "core/model.hpp"

namespace flexref::core {

class ImpactCounter {
 public:
  explicit ImpactCounter(const Model& model);
  /// Records the gaps at the initial state (no impact is counted for an initial contact).
  void start(const LoadContext& context, const State& state, Workspace& ws);
  /// Counts the onsets since the last call. Allocates nothing.
  void update(const LoadContext& context, const State& state, Workspace& ws);
  /// The same at a root a solver located: some switching function crossed zero. When the
  /// returned state shows no sign change (the root finder may return the state on either side
  /// of the crossing, within its time tolerance), the function nearest zero is the one that
  /// crossed and its side flips.
  void update_at_root(const LoadContext& context, const State& state, Workspace& ws);
  /// Impacts so far, one per wear channel.
  const std::vector<double>& counts() const { return counts_; }

 private:
  const Model* model_;
  std::vector<double> gaps_;
  std::vector<bool> separated_;
  std::vector<double> counts_;

  void count(std::size_t k, bool separated);
};

}  // namespace flexref::core
