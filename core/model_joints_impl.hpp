#pragma once
/// \file model_joints_impl.hpp
/// ModelTpl<S>'s ideal joints (docs/joints.md, "Ideal joints"): the constrained accelerations on
/// a tracker's rows, the tracker's advance at accepted states, violations and reactions. The
/// projections are model_projection_impl.hpp, the initial state's checks
/// model_initial_state_impl.hpp. Included by model_impl.hpp.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::core {
// --- Ideal joints (docs/joints.md, "Ideal joints") ----------------------------------------

template <typename S>
void ModelTpl<S>::apply_inverse_mass(int b, const Eigen::Ref<const Vector>& rhs,
                                     Eigen::Ref<Vector> out, Workspace& ws) const {
  const auto k = static_cast<std::size_t>(b);
  const Body& body = bodies_[k];
  if (body.is_flexible()) {
    FlexibleScratch& fs = ws.flexible[k];
    fs.x.template head<6>().setZero();  // the known rows take no constraint force
    if (formulation_ == FlexibleFormulation::kCoupled) {
      flexible::apply_coupled_tpl<S>(body.modal_mass(), fs.terms, rhs, fs.solve, fs.x);
    } else {
      flexible::apply_lte_tpl<S>(body.modal_mass(), fs.terms, rhs, fs.solve, fs.x);
    }
    out = fs.x;
    return;
  }
  // Rigid, about Br: M = diag(m 1, I_Br) on (v_WBr, ω̄); a pivot's translation and a prescribed
  // body's motion are fixed.
  out.setZero();
  if (body.is_prescribed()) return;
  if (body.is_free()) out.template head<3>() = rhs.template head<3>() / body.mass();
  out.template segment<3>(3).noalias() = body.I_Br_B_inverse() * rhs.template segment<3>(3);
}

template <typename S>
void ModelTpl<S>::stacked_inverse_mass(const Vector& in, Vector& out, Workspace& ws) const {
  ConstraintSolveTpl<S>& s = ws.constraint;
  out.setZero();
  for (int b = 0; b < num_bodies(); ++b) {
    const int o = layout_.offset(b);
    const int w = layout_.width(b);
    s.column.head(w) = in.segment(o, w);
    apply_inverse_mass(b, s.column.head(w), s.out.head(w), ws);
    out.segment(o, w) = s.out.head(w);
  }
}

template <typename S>
void ModelTpl<S>::apply_constraints(S t, const State& state, const ConstraintTracker& tracker,
                                    S stabilization, Workspace& ws,
                                    Accelerations& accelerations) const {
  ConstraintSolveTpl<S>& s = ws.constraint;
  constraints_->evaluate(t, ws.kinematics, layout_, s.rows);
  if (stabilization > S(0)) {
    // Baumgarte: γ − 2α (J v + Φ_t) − α² Φ (critically damped drift at the rate α).
    layout_.stack_velocities(state, s.v);
    add_baumgarte(stabilization, s);
  }
  layout_.stack_accelerations(accelerations, s.x);
  solve_constrained_accelerations(
      *constraints_, layout_,
      [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out, ws); },
      static_cast<double>(t), tracker, s);
  layout_.unstack_accelerations(s.x, accelerations);
}

template <typename S>
void ModelTpl<S>::evaluate_rows_at(S t, const State& state, Workspace& ws) const {
  pose_bodies(state, ws);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (!b.is_flexible()) continue;
    // The mass matrix at the state (its loads do not enter the factors).
    flexible_system(static_cast<int>(i), state[i], ws);
    FlexibleScratch& fs = ws.flexible[i];
    if (formulation_ == FlexibleFormulation::kCoupled) {
      flexible::factor_coupled_tpl<S>(b.modal_mass(), fs.terms, known_rows(b.motion()), fs.solve);
    } else {
      flexible::factor_lte_tpl<S>(fs.terms, known_rows(b.motion()), fs.solve);
    }
  }
  constraints_->evaluate(t, ws.kinematics, layout_, ws.constraint.rows);
}

template <typename S>
void ModelTpl<S>::factor_constraints_at(S t, const State& state, const ConstraintTracker& tracker,
                                        Workspace& ws) const {
  evaluate_rows_at(t, state, ws);
  factor_tracked_rows(
      *constraints_, layout_,
      [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out, ws); }, tracker,
      static_cast<double>(t), false, ws.constraint);
}

template <typename S>
typename ModelTpl<S>::ConstraintTracker ModelTpl<S>::make_constraint_tracker() const {
  ConstraintTracker tracker;
  if (!constraints_) return tracker;
  tracker.rows = active_rows_;
  tracker.J_accepted.build(constraints_->row_count(), layout_,
                           [&](int r) { return constraints_->row_bodies(r); });
  return tracker;
}

template <typename S>
void ModelTpl<S>::advance_tracker(S t, const State& state, ConstraintTracker& tracker,
                                  Workspace& ws, TrackerAdvance advance) const {
  if (!constraints_) return;
  if (advance == TrackerAdvance::kReference) {
    pose_bodies(state, ws);
    constraints_->evaluate(t, ws.kinematics, layout_, ws.constraint.rows);
    move_reference(static_cast<double>(t), ws.constraint, tracker);
    return;
  }
  evaluate_rows_at(t, state, ws);
  core::advance_tracker(
      *constraints_, layout_,
      [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out, ws); },
      static_cast<double>(t), advance != TrackerAdvance::kWithoutOrientation,
      advance == TrackerAdvance::kChooseRows, tracker, ws.constraint);
}

template <typename S>
RelativeJointViolationTpl<S> ModelTpl<S>::relative_violation(ConstraintSolveTpl<S>& s,
                                                             const State& state) const {
  const ConstraintRowsTpl<S>& rows = s.rows;
  stack_velocities(state, s.v);
  rows.jacobian.multiply(s.v, s.rate);
  s.rate += rows.phi_t;
  const Vector& rate = s.rate;
  // Velocity scale: the bodies' speeds (|v_Br| + |ω̄| ℓ) and the drives' rates.
  using std::abs;
  using std::max;
  S speed = S(0);
  for (const BodyState& b : state) {
    speed = max(speed, b.v_WBr.norm() + b.w_WB_B.norm() * joint_length_scale_);
  }
  for (Eigen::Index r = 0; r < rows.phi_t.size(); ++r) {
    const S scale = constraints_->is_length_row(static_cast<int>(r)) ? S(1) : joint_length_scale_;
    speed = max(speed, S(abs(rows.phi_t(r)) * scale));
  }
  RelativeJointViolationTpl<S> out;
  out.speed = speed;
  for (Eigen::Index r = 0; r < rows.phi.size(); ++r) {
    const int row = static_cast<int>(r);
    const bool length = constraints_->is_length_row(row);
    const S position = abs(rows.phi(r)) / (length ? joint_length_scale_ : S(1));
    const S velocity =
        speed > S(0) ? S(abs(rate(r)) * (length ? S(1) : joint_length_scale_) / speed) : S(0);
    // A NaN row is the worst (`>` alone would pass it over).
    if (position > out.position || (position != position && out.position == out.position)) {
      out.position = position;
      out.position_absolute = abs(rows.phi(r));
      out.position_row = row;
    }
    if (velocity > out.velocity || (velocity != velocity && out.velocity == out.velocity)) {
      out.velocity = velocity;
      out.velocity_absolute = abs(rate(r));
      out.velocity_row = row;
    }
  }
  return out;
}

template <typename S>
RelativeJointViolationTpl<S> ModelTpl<S>::relative_joint_violation(S t, const State& state,
                                                                   Workspace& ws) const {
  if (!constraints_) return {};
  pose_bodies(state, ws);
  constraints_->evaluate_rates(t, ws.kinematics, layout_, ws.constraint.rows);  // no γ read
  return relative_violation(ws.constraint, state);
}

template <typename S>
int ModelTpl<S>::constraint_rank(S t, const State& state, Workspace& ws, double tolerance) const {
  if (!constraints_) return 0;
  pose_bodies(state, ws);
  constraints_->evaluate(t, ws.kinematics, layout_, ws.constraint.rows);
  Eigen::ColPivHouseholderQR<Matrix> qr(
      row_normalized_transpose<S>(ws.constraint.rows.jacobian.dense()));
  qr.setThreshold(S(tolerance));
  return static_cast<int>(qr.rank());
}

template <typename S>
std::string ModelTpl<S>::singular_configuration_ahead(S t, const State& state, S step) const {
  using std::max;
  if (!constraints_) return {};
  Workspace ws = make_workspace();
  S speed = S(0);
  for (const BodyState& b : state) {
    speed = max(speed, S(b.v_WBr.norm() + b.w_WB_B.norm() * joint_length_scale_ + b.qd_f.norm()));
  }
  std::vector<S> spans;
  if (step > S(0)) spans.push_back(step);
  if (speed > S(0)) {
    for (const double fraction : {1e-4, 1e-3, 1e-2, 1e-1}) {
      spans.push_back(S(fraction) * joint_length_scale_ / speed);
    }
  }
  std::sort(spans.begin(), spans.end());
  ConstraintTracker tracker = make_constraint_tracker();
  try {
    advance_tracker(t, state, tracker, ws);
    for (const S& span : spans) {
      State moved = state;
      for (std::size_t b = 0; b < bodies_.size(); ++b) {
        const Body& body = bodies_[b];
        BodyState& x = moved[b];
        if (!body.is_prescribed()) {
          x.p_WBr += span * x.v_WBr;
          x.theta_WB = rotation::quaternion_multiply<S>(
              x.theta_WB, rotation::exp_quaternion(Vector3(span * x.w_WB_B)));
          x.theta_WB.normalize();
        }
        x.q_f += span * x.qd_f;
      }
      apply_prescribed_motion(t + span, moved);
      advance_tracker(t + span, moved, tracker, ws);
    }
  } catch (const SingularConfigurationError& e) {
    return e.what();
  }
  return {};
}

template <typename S>
S ModelTpl<S>::relative_position_violation(S t, const State& state, Workspace& ws) const {
  if (!constraints_) return S(0);
  pose_bodies(state, ws);
  constraints_->evaluate(t, ws.kinematics, layout_, ws.constraint.rows);
  return core::relative_position_violation<S>(*constraints_, ws.constraint.rows.phi,
                                              joint_length_scale_);
}

template <typename S>
std::vector<std::array<S, 2>> ModelTpl<S>::constraint_violations(S t, const State& state,
                                                                 Workspace& ws) const {
  std::vector<std::array<S, 2>> out;
  if (!constraints_) return out;
  pose_bodies(state, ws);
  ConstraintRowsTpl<S>& rows = ws.constraint.rows;
  constraints_->evaluate(t, ws.kinematics, layout_, rows);
  Vector v(layout_.size());
  stack_velocities(state, v);
  return joint_violations<S>(*constraints_, rows, v);
}

template <typename S>
std::vector<JointReactionTpl<S>> ModelTpl<S>::joint_reactions(const LoadContext& context,
                                                              const State& state,
                                                              const ConstraintTracker& tracker,
                                                              Workspace& ws) const {
  std::vector<JointReaction> out;
  if (!constraints_) return out;
  Accelerations accelerations = make_accelerations();
  compute_accelerations(context, state, tracker, ws, accelerations);
  return joint_reactions_from_solve<S>(*constraints_, ws.kinematics, layout_,
                                       joint_multipliers(ws));
}

}  // namespace flexref::core
