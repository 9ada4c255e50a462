#pragma once
/// \file model_projection_impl.hpp
/// ModelTpl<S>'s projections onto the ideal joints (docs/joints.md, "Initial state"; Hairer,
/// Lubich & Wanner, Geometric Numerical Integration IV.4): the positions by Newton's method in
/// the mass metric, then the velocities, on a tracker's rows. Included by model_impl.hpp.
#include <limits>

#include "core/model.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::core {

template <typename S>
void ModelTpl<S>::apply_position_increment(const Vector& delta, State& state) const {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    if (body.is_prescribed() && !body.is_flexible()) continue;
    const int o = layout_.offset(static_cast<int>(b));
    BodyState& x = state[b];
    if (!body.is_prescribed()) {
      x.p_WBr += delta.template segment<3>(o);
      // A ← A exp(δφ̃): θ ← θ ⊗ exp(δφ), renormalized.
      x.theta_WB = rotation::quaternion_multiply<S>(
          x.theta_WB, rotation::exp_quaternion(Vector3(delta.template segment<3>(o + 3))));
      x.theta_WB.normalize();
    }
    x.q_f += delta.segment(o + 6, body.mode_count());
  }
}

template <typename S>
InitialProjection ModelTpl<S>::project(S t, State& state, const ConstraintTracker& tracker,
                                       Workspace& ws) const {
  InitialProjection before;
  if (!constraints_) return before;
  ConstraintSolveTpl<S>& s = ws.constraint;
  factor_constraints_at(t, state, tracker, ws);
  const RelativeJointViolationTpl<S> first = relative_violation(s, state);
  before.position = static_cast<double>(first.position);
  // Newton on Φ = 0 in the mass metric: converged when the relative violation is a few ε (the
  // round-off of Φ itself, a sum of products of lengths of size ℓ).
  project_positions<S>([&] { factor_constraints_at(t, state, tracker, ws); },
                       [&] {
                         return core::relative_position_violation<S>(*constraints_, s.rows.phi,
                                                                     joint_length_scale_);
                       },
                       [&](const Vector& delta) { apply_position_increment(delta, state); },
                       S(8) * std::numeric_limits<S>::epsilon(), s);
  before.velocity = static_cast<double>(relative_violation(s, state).velocity);
  project_velocities(t, state, tracker, ws);
  return before;
}

template <typename S>
void ModelTpl<S>::project_velocities(S t, State& state, const ConstraintTracker& tracker,
                                     Workspace& ws) const {
  if (!constraints_) return;
  ConstraintSolveTpl<S>& s = ws.constraint;
  factor_constraints_at(t, state, tracker, ws);
  stack_velocities(state, s.v);
  s.rows.jacobian.multiply(s.v, s.rate);
  s.rate += s.rows.phi_t;
  constraint_correction<S>(s.rate, s);
  layout_.add_to_velocities(s.x, state);
}

}  // namespace flexref::core
