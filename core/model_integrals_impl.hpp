#pragma once
/// \file model_integrals_impl.hpp
/// ModelTpl<S>'s switching functions, tracked integrals and wear channels (docs/output.md,
/// "Energy balance"; docs/wear.md): the dissipated power, the applied and drive power, each
/// contact's wear samples and worn depths' rates. Included by model_impl.hpp.
#include <span>

#include "core/model.hpp"

namespace flexref::core {

template <typename S>
template <typename Evaluate>
void ModelTpl<S>::for_each_switching_element(std::span<S> out, Evaluate&& evaluate) const {
  std::size_t offset = 0;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const auto count = static_cast<std::size_t>(elements_[e]->switching_function_count());
    if (count == 0) continue;
    evaluate(*elements_[e], e, out.subspan(offset, count));
    offset += count;
  }
}

template <typename S>
void ModelTpl<S>::switching_functions(const LoadContext& context, const State& state, Workspace& ws,
                                      std::span<S> g) const {
  pose_bodies(state, ws);
  for_each_switching_element(g, [&](const ForceElement& e, std::size_t j, std::span<S> values) {
    e.switching_functions(element_context(context, ws, j), ws.kinematics, values);
  });
}

template <typename S>
void ModelTpl<S>::clamp_functions(const LoadContext& context, const State& state, Workspace& ws,
                                  std::span<S> c) const {
  pose_bodies(state, ws);
  for_each_switching_element(c, [&](const ForceElement& e, std::size_t j, std::span<S> values) {
    e.clamp_functions(element_context(context, ws, j), ws.kinematics, values);
  });
}

template <typename S>
typename ModelTpl<S>::Loads ModelTpl<S>::compute_wrenches_and_rates(
    const LoadContext& context, const State& state, Workspace& ws, std::span<S> rates,
    std::span<S> g, std::span<S> c) const {
  pose_bodies(state, ws);
  for (WrenchTpl<S>& w : ws.wrenches) w.set_zero();
  const bool with_rates = tracks_work() && !rates.empty();
  // Ẇ_d = Σ q̇_fᵀ D q̇_f + the elements' dissipation (dissipated_power's sum, in its order).
  S dissipation = with_rates ? modal_dissipated_power(state) : S(0);
  std::size_t offset = 0;
  for (std::size_t j = 0; j < elements_.size(); ++j) {
    const ForceElementTpl<S>& e = *elements_[j];
    const auto count = static_cast<std::size_t>(e.switching_function_count());
    const int channel = element_channels_[j];
    std::span<WearSampleTpl<S>> wear;
    if (with_rates && channel >= 0) wear = {&ws.wear[static_cast<std::size_t>(channel)], 1};
    e.add_wrenches_and_rates(element_context(context, ws, j), ws.kinematics, ws.wrenches,
                             with_rates ? &dissipation : nullptr, wear,
                             g.empty() ? g : g.subspan(offset, count),
                             c.empty() ? c : c.subspan(offset, count));
    offset += count;
  }
  const Loads loads(context, state);
  if (!with_rates) return loads;
  // Then Ẇ_a = the applied power and each wear channel's |F_t·v_t| (integral_rates' layout).
  const IntegralLayout& k = integral_layout_;
  rates[0] = dissipation;
  if (k.applied >= 0) rates[static_cast<std::size_t>(k.applied)] = applied_power(context, ws);
  if (k.drive >= 0) rates[static_cast<std::size_t>(k.drive)] = S(0);
  for (std::size_t ch = 0; ch < ws.wear.size(); ++ch) {
    rates[static_cast<std::size_t>(k.first_wear) + ch] = ws.wear[ch].wear_power;
  }
  return loads;
}

template <typename S>
S ModelTpl<S>::dissipated_power(const LoadContext& context, const State& state,
                                Workspace& ws) const {
  pose_bodies(state, ws);
  S p = modal_dissipated_power(state);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    p += elements_[e]->dissipated_power(element_context(context, ws, e), ws.kinematics);
  }
  return p;
}

template <typename S>
S ModelTpl<S>::modal_dissipated_power(const State& state) const {
  S p = S(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].is_flexible()) {
      // q̇_fᵀ D q̇_f with D = diag(d_i)
      p += state[i].qd_f.dot(bodies_[i].modal_damping().cwiseProduct(state[i].qd_f));
    }
  }
  return p;
}

template <typename S>
S ModelTpl<S>::applied_power(const LoadContext& context, const Workspace& ws) const {
  S p = S(0);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    p += elements_[e]->applied_power(element_context(context, ws, e), ws.kinematics);
  }
  return p;
}

// --- Wear channels and tracked integrals (docs/output.md): W_d, the applied work W_a of loads
// that keep doing work, and each contact's wear work ∫ |F_t·v_t| dt. -----------------------

template <typename S>
void ModelTpl<S>::wear_samples(const LoadContext& context, const State& state,
                               Workspace& ws) const {
  pose_bodies(state, ws);
  for (std::size_t c = 0; c < wear_elements_.size(); ++c) {
    const auto e = static_cast<std::size_t>(wear_elements_[c]);
    elements_[e]->wear_samples(element_context(context, ws, e), ws.kinematics,
                               std::span<WearSampleTpl<S>>(&ws.wear[c], 1));
  }
}

template <typename S>
void ModelTpl<S>::wear_depth_rates(const LoadContext& context, const State& state, Workspace& ws,
                                   std::span<S> rates) const {
  if (wear_depth_count_ == 0) return;
  pose_bodies(state, ws);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const auto count = static_cast<std::size_t>(elements_[e]->wear_depth_count());
    if (count == 0) continue;
    elements_[e]->wear_depth_rates(element_context(context, ws, e), ws.kinematics,
                                   rates.subspan(element_depth_first_[e], count));
  }
}

template <typename S>
S ModelTpl<S>::wear_depth_max(int channel, const State& state) const {
  const int count = channel_depth_count(channel);
  if (count == 0) return S(0);
  return state.wear_depth.segment(channel_depth_first(channel), count).maxCoeff();
}

template <typename S>
S ModelTpl<S>::wear_volume(int channel, const State& state) const {
  const int first = channel_depth_first(channel);
  S v = S(0);
  for (int k = first; k < first + channel_depth_count(channel); ++k) {
    v += S(wear_depth_areas_[static_cast<std::size_t>(k)]) * state.wear_depth(k);
  }
  return v;
}

template <typename S>
void ModelTpl<S>::integral_rates(const LoadContext& context, const State& state, Workspace& ws,
                                 std::span<S> rates, const Vector* constraint_force,
                                 const ConstraintTracker* tracker) const {
  const IntegralLayout& k = integral_layout_;
  if (k.drive >= 0) {
    // The joints' power first (a constrained solve of its own when the caller has none: it
    // overwrites the loads in ws, which the rates below evaluate again).
    if (constraint_force == nullptr) {
      const Loads loads = compute_wrenches(context, state, ws);
      free_accelerations(loads, ws, ws.integral_accelerations);
      apply_constraints(context.t, state, tracker != nullptr ? *tracker : default_tracker_, S(0),
                        ws, ws.integral_accelerations);
      constraint_force = &ws.constraint.force;
    }
    rates[static_cast<std::size_t>(k.drive)] = constraint_power(state, *constraint_force, ws);
  }
  rates[0] = dissipated_power(context, state, ws);  // poses the bodies
  if (k.count == 0) return;
  if (k.applied >= 0) rates[static_cast<std::size_t>(k.applied)] = applied_power(context, ws);
  for (std::size_t c = 0; c < wear_elements_.size(); ++c) {
    const auto e = static_cast<std::size_t>(wear_elements_[c]);
    elements_[e]->wear_samples(element_context(context, ws, e), ws.kinematics,
                               std::span<WearSampleTpl<S>>(&ws.wear[c], 1));
    rates[static_cast<std::size_t>(k.first_wear) + c] = ws.wear[c].wear_power;
  }
}

template <typename S>
S ModelTpl<S>::constraint_power(const State& state, const Vector& constraint_force,
                                Workspace& ws) const {
  stack_velocities(state, ws.constraint.v);
  return ws.constraint.v.dot(constraint_force);
}

}  // namespace flexref::core
