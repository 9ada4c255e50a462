#pragma once
/// \file ode_system_impl.hpp
/// OdeSystemTpl<S>'s definitions, included by the translation unit of each precision
/// (model_instances_{double,extended,quad}.cpp).
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "precision/model_conversion.hpp"
#include "precision/ode_system.hpp"
#include "reference/form_layout.hpp"
#include "reference/method_choice.hpp"
#include "scene/build_model.hpp"
#include "trajectory/column_order.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {

template <typename S>
OdeSystemTpl<S>::OdeSystemTpl(const scene::SceneSpec& spec, core::FlexibleFormulation formulation,
                              double output_spacing)
    : OdeSystemTpl(scene::build_model(spec, formulation), spec.name, output_spacing) {}

template <typename S>
OdeSystemTpl<S>::OdeSystemTpl(const core::Model& built, const std::string& name,
                              double output_spacing)
    : model_(model_in<S>(built, name)),
      columns_(trajectory::trajectory_columns(built)),
      discontinuities_(built.discontinuities()) {
  for (int i = 0; i < model_.num_bodies(); ++i) {
    const core::BodyTpl<S>& b = model_.body(i);
    if (!b.is_prescribed()) continue;
    has_prescribed_ = true;
    const core::AngleLaw& law = b.description().prescribed.law;
    if (law.kind == core::AngleLaw::Kind::kSpinUp) discontinuities_.push_back(law.spin_up_time);
  }
  std::sort(discontinuities_.begin(), discontinuities_.end());
  discontinuities_.erase(std::unique(discontinuities_.begin(), discontinuities_.end()),
                         discontinuities_.end());
  depth_offset_ = blocks_.empty() ? 0 : blocks_.back().end;
  integrals_offset_ = depth_offset_ + model_.wear_depth_count();
  integral_count_ = model_.integral_layout().count;
  fixed_ = model_.initial_state();
  ws_ = model_.make_workspace();
  tracker_ = model_.make_constraint_tracker();
  state_ = model_.initial_state();
  accelerations_ = model_.make_accelerations();
  rates_.assign(static_cast<std::size_t>(integral_count_), S(0));
  depth_rates_.assign(static_cast<std::size_t>(model_.wear_depth_count()), S(0));
  gaps_.assign(static_cast<std::size_t>(model_.switching_function_count()), S(0));
  clamps_ = gaps_;
  if (model_.has_constraints()) {
    // Baumgarte's rate of the double ODE references (reference/method_choice.hpp).
    stabilization_ = S(reference::constraint_stabilization_rate(built, output_spacing));
  }
  energy0_ = energy(S(0), initial_state());
}

template <typename S>
std::vector<S> OdeSystemTpl<S>::initial_state() const {
  std::vector<S> y(static_cast<std::size_t>(state_size()), S(0));  // the integrals start at 0
  state_ = model_.initial_state();
  pack(y);
  return y;
}

template <typename S>
void OdeSystemTpl<S>::unpack(S t, const std::vector<S>& y) const {
  reference::unpack_bodies<S>(blocks_, fixed_, depth_offset_, y.data(), state_);
  if (has_prescribed_) model_.apply_prescribed_motion(t, state_, ws_);
}

template <typename S>
void OdeSystemTpl<S>::pack(std::vector<S>& y) const {
  reference::pack_bodies<S>(blocks_, depth_offset_, state_, y.data());
}

template <typename S>
void OdeSystemTpl<S>::interleave_switching(std::vector<S>& values) const {
  values.resize(2 * gaps_.size());
  for (std::size_t i = 0; i < gaps_.size(); ++i) {
    values[2 * i] = gaps_[i];
    values[2 * i + 1] = clamps_[i];
  }
}

template <typename S>
void OdeSystemTpl<S>::switching_functions(S t, const std::vector<S>& y,
                                          std::vector<S>& values) const {
  unpack(t, y);
  const core::LoadContextTpl<S> ctx = context(t, static_cast<double>(t));
  model_.switching_functions(ctx, state_, ws_, gaps_);
  model_.clamp_functions(ctx, state_, ws_, clamps_);
  interleave_switching(values);
}

template <typename S>
void OdeSystemTpl<S>::derivative(const std::vector<S>& y, std::vector<S>& dydt, S t,
                                 double t_segment, std::vector<S>* switching) const {
  unpack(t, y);
  // The loads, and in the same pass over the elements the integrals' rates and the switching
  // values (they come along with every evaluation: switched_integration.hpp).
  const core::LoadsTpl<S> loads =
      model_.compute_wrenches_and_rates(context(t, t_segment), state_, ws_, rates_, gaps_, clamps_);
  model_.accelerations_from_wrenches(loads, tracker_, ws_, accelerations_, stabilization_);
  if (const int drive = model_.integral_layout().drive; drive >= 0) {
    // The drives' power from this evaluation's constrained solve.
    rates_[static_cast<std::size_t>(drive)] =
        model_.constraint_power(state_, model_.joint_multipliers(ws_).force(), ws_);
  }
  if (switching != nullptr) interleave_switching(*switching);
  dydt.resize(y.size());
  for (int i = 0; i < model_.num_bodies(); ++i) {
    const reference::BodyBlock& k = blocks_[static_cast<std::size_t>(i)];
    const core::BodyStateTpl<S>& x = state_[static_cast<std::size_t>(i)];
    const core::BodyAccelerationTpl<S>& a = accelerations_[static_cast<std::size_t>(i)];
    const auto at = [&dydt](int offset, int j) -> S& {
      return dydt[static_cast<std::size_t>(offset + j)];
    };
    // ṗ = v; θ̇ = ½ θ ⊗ (0, ω̄) with y's θ; v̇ = a; ω̄̇ = α̅ (a pivot has no p, v blocks).
    if (k.p >= 0) {
      for (int j = 0; j < 3; ++j) {
        at(k.p, j) = y[static_cast<std::size_t>(k.v + j)];
        at(k.v, j) = a.a_WBr(j);
      }
    }
    if (k.theta >= 0) {
      const S h(0.5);
      const auto o = static_cast<std::size_t>(k.theta);
      const S e0 = y[o], e1 = y[o + 1], e2 = y[o + 2], e3 = y[o + 3];
      const Vector3& w = x.w_WB_B;
      at(k.theta, 0) = -h * (e1 * w(0) + e2 * w(1) + e3 * w(2));
      at(k.theta, 1) = h * (e0 * w(0) + e2 * w(2) - e3 * w(1));
      at(k.theta, 2) = h * (e0 * w(1) + e3 * w(0) - e1 * w(2));
      at(k.theta, 3) = h * (e0 * w(2) + e1 * w(1) - e2 * w(0));
      for (int j = 0; j < 3; ++j) at(k.w, j) = a.alpha_WB_B(j);
    }
    for (int j = 0; j < k.n; ++j) {
      at(k.q, j) = y[static_cast<std::size_t>(k.qd + j)];
      at(k.qd, j) = a.qdd_f(j);
    }
  }
  if (!depth_rates_.empty()) {
    // h' = the contacts' wear rates (docs/wear.md)
    model_.wear_depth_rates(context(t, t_segment), state_, ws_, depth_rates_);
    std::copy(depth_rates_.begin(), depth_rates_.end(),
              dydt.begin() + static_cast<std::ptrdiff_t>(depth_offset_));
  }
  for (int k = 0; k < integral_count_; ++k) {
    dydt[static_cast<std::size_t>(integrals_offset_ + k)] = rates_[static_cast<std::size_t>(k)];
  }
}

template <typename S>
S OdeSystemTpl<S>::energy(S t, const std::vector<S>& y) const {
  unpack(t, y);
  return model_.kinetic_energy(state_) +
         model_.potential_energy(context(t, static_cast<double>(t)), state_, ws_);
}

template <typename S>
S OdeSystemTpl<S>::relative_position_violation(S t, const std::vector<S>& y) const {
  unpack(t, y);
  return model_.relative_position_violation(t, state_, ws_);
}

template <typename S>
core::RelativeJointViolationTpl<S> OdeSystemTpl<S>::relative_joint_violation(
    S t, const std::vector<S>& y) const {
  unpack(t, y);
  return model_.relative_joint_violation(t, state_, ws_);
}

template <typename S>
S OdeSystemTpl<S>::project(S t, std::vector<S>& y) const {
  if (!has_constraints()) return S(0);
  const S before = relative_position_violation(t, y);
  model_.project(t, state_, tracker_, ws_);
  pack(y);
  return before;
}

template <typename S>
std::vector<S> OdeSystemTpl<S>::output_row(S t, const std::vector<S>& y,
                                           const std::vector<double>& impacts) const {
  std::vector<S> row;
  row.reserve(columns_.size());
  const core::LoadContextTpl<S> ctx = context(t, static_cast<double>(t));
  unpack(t, y);
  // The drives' torques and the joints' reactions at the accelerations of (t, y), on the
  // right-limit branch at t; the reactions from the plain index-1 form (no stabilization
  // terms: core::ModelTpl::joint_reactions).
  if (has_constraints())
    model_.advance_tracker(t, state_, tracker_, ws_, core::TrackerAdvance::kWithoutOrientation);
  std::vector<core::JointReactionTpl<S>> reactions;
  std::optional<core::LoadsTpl<S>> loads;
  if (has_prescribed_)
    loads = model_.compute_accelerations(ctx, state_, tracker_, ws_, accelerations_);
  if (has_constraints()) reactions = model_.joint_reactions(ctx, state_, tracker_, ws_);
  const auto integrals = static_cast<std::size_t>(integrals_offset_);
  const core::IntegralLayout& layout = model_.integral_layout();
  const S work = layout.count > 0 ? y[integrals] : S(0);
  const S applied_work =
      layout.applied >= 0 ? y[integrals + static_cast<std::size_t>(layout.applied)] : S(0);
  const S drive_work =
      layout.drive >= 0 ? y[integrals + static_cast<std::size_t>(layout.drive)] : S(0);
  // What several groups share, evaluated where the first of them is written.
  std::vector<std::array<S, 2>> violations;
  S e = S(0);
  bool wear_sampled = false;
  const auto push3 = [&row](const Vector3& v) { row.insert(row.end(), {v(0), v(1), v(2)}); };
  // The columns after t (trajectory/column_order.hpp: the double table's order).
  trajectory::for_each_column_group(model_, [&](const trajectory::ColumnGroup& g) {
    using K = trajectory::ColumnKind;
    const auto owner = static_cast<std::size_t>(g.owner);
    switch (g.kind) {
      case K::time:
        break;
      case K::position:
        push3(model_.p_WBo(g.owner, state_[owner]));
        break;
      case K::rotation:
        row.insert(row.end(), state_[owner].theta_WB.data(), state_[owner].theta_WB.data() + 4);
        break;
      case K::velocity:
        push3(model_.v_WBo(g.owner, state_[owner]));
        break;
      case K::angular_velocity:
        push3(state_[owner].w_WB_B);
        break;
      case K::point:
        push3(model_.p_WP(
            g.owner, state_[owner],
            model_.body(g.owner).description().points[static_cast<std::size_t>(g.point)]));
        break;
      case K::mode:
        row.insert(row.end(), state_[owner].q_f.data(), state_[owner].q_f.data() + g.count);
        break;
      case K::mode_rate:
        row.insert(row.end(), state_[owner].qd_f.data(), state_[owner].qd_f.data() + g.count);
        break;
      case K::drive_torque:
        row.push_back(model_.driving_torque(g.owner, *loads, accelerations_[owner], ws_));
        break;
      case K::reaction_force:
        // Per joint: its reaction on its first body (force, torque about the joint point;
        // world) and its largest position and velocity violation.
        if (violations.empty()) violations = model_.constraint_violations(t, state_, ws_);
        push3(reactions[owner].f_W);
        break;
      case K::reaction_torque:
        push3(reactions[owner].tau_W);
        break;
      case K::violation:
        row.push_back(violations[owner][0]);
        break;
      case K::violation_rate:
        row.push_back(violations[owner][1]);
        break;
      case K::energy:
        e = model_.kinetic_energy(state_) + model_.potential_energy(ctx, state_, ws_);
        row.push_back(e);
        break;
      case K::dissipated_work:
        row.push_back(work);
        break;
      case K::applied_work:
        row.push_back(applied_work);
        break;
      case K::drive_work:
        row.push_back(drive_work);
        break;
      case K::energy_balance:
        // E(t) − E(0) + W_d(t) − W_a(t) − W_drive(t)
        row.push_back(e - energy0_ + work - applied_work - drive_work);
        break;
      case K::normal_force:
        // Per channel Σ F_n, the slip speed of its most loaded support or pair (the element's
        // wear_samples), the wear work and the impacts counted by the caller.
        if (!wear_sampled) {
          model_.wear_samples(ctx, state_, ws_);
          wear_sampled = true;
        }
        row.push_back(ws_.wear[owner].normal_force);
        break;
      case K::slip_speed:
        row.push_back(ws_.wear[owner].slip_speed);
        break;
      case K::wear_work:
        row.push_back(y[integrals + static_cast<std::size_t>(layout.first_wear) + owner]);
        break;
      case K::impacts:
        row.push_back(owner < impacts.size() ? S(impacts[owner]) : S(0));
        break;
      case K::wear_depth:
        // The worn depths: the largest, the volume, each point's or sector's.
        row.push_back(model_.wear_depth_max(g.owner, state_));
        break;
      case K::wear_volume:
        row.push_back(model_.wear_volume(g.owner, state_));
        break;
      case K::depth: {
        const int first = model_.channel_depth_first(g.owner);
        for (int k = first; k < first + g.count; ++k) row.push_back(state_.wear_depth(k));
        break;
      }
      case K::unknown:
        break;
    }
  });
  return row;
}

}  // namespace flexref::precision
