#include "lie/c1.hpp"

#include <Eigen/LU>  // Matrix3d::inverse
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "lie/c1_newton.hpp"
#include "lie/scheme_support.hpp"
#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"

namespace flexref::lie {

using Eigen::Matrix3d;
using Eigen::Vector3d;

C1Stepper::C1Stepper(const core::Model& model)
    : model_(model),
      state_(model.initial_state()),
      next_(state_),
      mid_(state_),
      acc_(model.make_accelerations()),
      acc_next_(model.make_accelerations()),
      R_n_transpose_(state_.size(), Matrix3d::Identity()),
      b_(state_.size(), Vector3d::Zero()),
      residual_(state_.size(), Vector3d::Zero()),
      jacobian_(state_.size(), Matrix3d::Identity()),
      w_accepted_(state_.size(), Vector3d::Zero()),
      delta_(state_.size(), Vector3d::Zero()),
      ws_(model.make_workspace()),
      wear_(model) {
  detail::require_hybrid_scheme_model(model, "c1");
  for (const core::Body& body : model.bodies()) {
    has_free_body_ = has_free_body_ || body.is_free() || body.is_flexible();
  }
}

double C1Stepper::force_evaluations_per_step() const {
  if (steps_ == 0) return has_free_body_ ? 2.0 : 1.0;
  return static_cast<double>(evaluations_) / static_cast<double>(steps_);
}

void C1Stepper::initialize(double t0, const core::State& state) {
  if (state.size() != state_.size()) {
    throw std::invalid_argument("c1: the state has a different number of bodies than the model");
  }
  time_ = t0;
  state_ = state;
  next_ = state;
  mid_ = state;
  // t_segment = t0 selects the branch on the right of t0; the first step re-evaluates on its
  // own segment [t0, t0 + h).
  model_.compute_accelerations(core::LoadContext{t0, t0}, state_, ws_, acc_);
  wear_.start(core::LoadContext{t0, t0}, state_, ws_);
  restart_pending_ = true;
  newton_iterations_ = 0;
  max_newton_iterations_ = 0;
  evaluations_ = 0;
  steps_ = 0;
}

void C1Stepper::restart(double h) {
  // a_n = f_n/m (right limit at t_n); A_n from the Euler equation (the Newton predictor).
  model_.compute_accelerations(core::LoadContext{time_, time_ + 0.5 * h}, state_, ws_, acc_);
  wear_.start(core::LoadContext{time_, time_ + 0.5 * h}, state_, ws_);
  ++evaluations_;
}

C1Stepper::NewtonOutcome C1Stepper::solve_balance(double t_n, double h) {
  const core::LoadContext midpoint{t_n + 0.5 * h, t_n + 0.5 * h};
  const std::size_t n_bodies = state_.size();
  NewtonOutcome outcome;
  double merit = std::numeric_limits<double>::infinity();  // Σ |r|² at the accepted iterate
  double step_length = 1.0;                                // α of the current trial
  double previous_relative = std::numeric_limits<double>::infinity();  // at the last iterate
  for (int evaluations = 0; evaluations < kMaxNewtonEvaluations; ++evaluations) {
    for (std::size_t i = 0; i < n_bodies; ++i) {
      const core::BodyState& s = state_[i];
      // Θ ← (h/2)(W_n + W_{n+1})
      const Vector3d theta = detail::c1_increment(s.w_WB_B, next_[i].w_WB_B, h);
      // R_{n+½} ← R_n exp(Θ̃/2),  W_{n+½} ← ½ (W_n + W_{n+1})
      mid_[i].theta_WB =
          rotation::quaternion_multiply(s.theta_WB, rotation::exp_quaternion(0.5 * theta));
      detail::renormalize_unit_product(mid_[i].theta_WB);
      mid_[i].w_WB_B = 0.5 * (s.w_WB_B + next_[i].w_WB_B);
    }
    model_.apply_prescribed_motion(t_n + 0.5 * h, mid_);
    // Γ_{n+½} at t_{n+½} and the midpoint configuration.
    model_.compute_wrenches(midpoint, mid_, ws_);
    ++evaluations_;

    double trial_merit = 0.0;
    outcome.relative_residual = 0.0;
    for (std::size_t i = 0; i < n_bodies; ++i) {
      if (model_.body(static_cast<int>(i)).is_prescribed()) {
        // W follows the law: nothing to solve (zero residual, zero correction).
        residual_[i].setZero();
        jacobian_[i].setIdentity();
        continue;
      }
      const Matrix3d& J = model_.body(static_cast<int>(i)).I_Br_B();
      const Vector3d& W_n = state_[i].w_WB_B;
      const Vector3d& W = next_[i].w_WB_B;
      const Vector3d impulse_B = h * (R_n_transpose_[i] * ws_.wrenches[i].tau_Br_W);
      const Vector3d J_W_n = J * W_n;
      // b ← J W_n + h R_nᵀ Γ_{n+½}
      b_[i] = J_W_n + impulse_B;
      // r ← J W − exp(−Θ̃) b,  K ← J − (h/2)(exp(−Θ̃) b)~ J_r(Θ)
      const detail::C1Linearization linearization = detail::c1_linearize(J, b_[i], W_n, W, h);
      residual_[i] = linearization.residual;
      jacobian_[i] = linearization.jacobian;
      // Scale of the residual's terms, including the individual torques that make up the net
      // impulse (their round-off survives when they cancel).
      const double scale = detail::max_abs(J * W) + detail::max_abs(J_W_n) +
                           detail::max_abs(impulse_B) + h * ws_.wrenches[i].torque_magnitude;
      const double relative = detail::max_abs(residual_[i]) / (scale > 0.0 ? scale : 1.0);
      if (!std::isfinite(relative)) {
        outcome.finite = false;
        return outcome;
      }
      if (relative > outcome.relative_residual) {
        outcome.relative_residual = relative;
        outcome.worst_body = static_cast<int>(i);
      }
      trial_merit += residual_[i].squaredNorm();
    }
    // Backtracking (only far from the root, when h|W| ≳ 1): a full step that does not
    // decrease Σ|r|² (Armijo, slope 1e-4) is halved, down to 1/64.
    if (trial_merit > (1.0 - 1e-4 * step_length) * merit && step_length > kMinStepLength) {
      step_length *= 0.5;
      for (std::size_t i = 0; i < n_bodies; ++i) {
        next_[i].w_WB_B = w_accepted_[i] - step_length * delta_[i];
      }
      continue;
    }
    merit = trial_merit;
    // Velocity-dependent loads (friction, dampers): add −exp(−Θ̃) h R_nᵀ ∂Γ_{n+½}/∂W to K by
    // forward differences (docs/schemes.md, "C1 on velocity-dependent loads").
    if (model_.has_velocity_dependent_loads() &&
        outcome.relative_residual > detail::kNewtonTolerance) {
      add_load_jacobian(t_n, h);
    }
    // W ← W − K⁻¹ r   (also after the test has passed: the correction then only removes the
    // last ≤ 1e-14 of the error and costs no evaluation, and without it that remainder would
    // bias every step the same way and add up over a run)
    ++outcome.iterations;
    for (std::size_t i = 0; i < n_bodies; ++i) {
      w_accepted_[i] = next_[i].w_WB_B;
      delta_[i] = jacobian_[i].inverse() * residual_[i];
      next_[i].w_WB_B = w_accepted_[i] - delta_[i];
    }
    step_length = 1.0;
    if (outcome.relative_residual <= detail::kNewtonTolerance ||
        detail::newton_stagnated(outcome.relative_residual, previous_relative)) {
      outcome.converged = true;
      return outcome;
    }
    previous_relative = outcome.relative_residual;
  }
  return outcome;
}

void C1Stepper::add_load_jacobian(double t_n, double h) {
  const core::LoadContext midpoint{t_n + 0.5 * h, t_n + 0.5 * h};
  for (std::size_t i = 0; i < state_.size(); ++i) {
    if (model_.body(static_cast<int>(i)).is_prescribed()) continue;
    const core::BodyState& s = state_[i];
    const Vector3d W = next_[i].w_WB_B;
    const core::BodyState mid_saved = mid_[i];
    const Matrix3d exp_minus = rotation::exp_so3(-detail::c1_increment(s.w_WB_B, W, h));
    // ε: the square root of the unit round-off times the size of W (forward differences).
    const double eps = 1.5e-8 * std::max(1.0, W.cwiseAbs().maxCoeff());
    for (int k = 0; k < 3; ++k) {
      next_[i].w_WB_B = W;
      next_[i].w_WB_B(k) += eps;
      const Vector3d theta = detail::c1_increment(s.w_WB_B, next_[i].w_WB_B, h);
      mid_[i].theta_WB =
          rotation::quaternion_multiply(s.theta_WB, rotation::exp_quaternion(0.5 * theta));
      detail::renormalize_unit_product(mid_[i].theta_WB);
      mid_[i].w_WB_B = 0.5 * (s.w_WB_B + next_[i].w_WB_B);
      model_.compute_wrenches(midpoint, mid_, ws_);
      ++evaluations_;
      // ∂b/∂W_k = h R_nᵀ (Γ(W + ε e_k) − Γ(W))/ε,  with b = J W_n + h R_nᵀ Γ
      const Vector3d b_plus = model_.body(static_cast<int>(i)).I_Br_B() * s.w_WB_B +
                              h * (R_n_transpose_[i] * ws_.wrenches[i].tau_Br_W);
      jacobian_[i].col(k) -= exp_minus * ((b_plus - b_[i]) / eps);
    }
    next_[i].w_WB_B = W;
    mid_[i] = mid_saved;
  }
}

StepStatus C1Stepper::step(double h) {
  const double t_n = time_;
  const double t_np1 = t_n + h;
  if (restart_pending_ || detail::starts_on_discontinuity(model_.discontinuities(), t_n, h)) {
    restart(h);
  }
  const std::size_t n_bodies = state_.size();
  // The worn depths the step's loads see: h_n + Δt ḣ_n at t_{n+1}, h_n + ½ Δt ḣ_n at t_{n+½}.
  wear_.predict(state_, h, next_);
  wear_.predict(state_, 0.5 * h, mid_);

  // 1. Translation (explicit) and the Newton predictor.
  for (std::size_t i = 0; i < n_bodies; ++i) {
    const core::BodyState& s = state_[i];
    core::BodyState& s1 = next_[i];
    core::BodyState& sm = mid_[i];
    const Vector3d& a_n = acc_[i].a_WBr;
    if (model_.body(static_cast<int>(i)).is_free()) {
      // x_{n+1} ← x_n + h v_n + ½ h² a_n
      s1.p_WBr = s.p_WBr + h * s.v_WBr + (0.5 * h * h) * a_n;
      // x_{n+½} ← ½ (x_n + x_{n+1}),  v_{n+½} ← v_n + ½ h a_n   (predictor)
      sm.p_WBr = 0.5 * (s.p_WBr + s1.p_WBr);
      sm.v_WBr = s.v_WBr + (0.5 * h) * a_n;
    } else {
      s1.p_WBr = s.p_WBr;
      sm.p_WBr = s.p_WBr;
      s1.v_WBr.setZero();
      sm.v_WBr.setZero();
    }
    R_n_transpose_[i] = rotation::rotation_matrix(s.theta_WB).transpose();
    // W_{n+1} ← W_n + h A_n   (predictor)
    s1.w_WB_B = s.w_WB_B + h * acc_[i].alpha_WB_B;
    // q_{n+½} ← ½ (q_n + q_{n+1}) below, once q_{n+1} is predicted.
  }
  // q_{n+1} ← q_n + h q̇_n + ½ h² q̈_n;  prescribed bodies: their law at t_{n+1}.
  detail::predict_modes(model_, state_, acc_, h, t_np1, next_);
  for (std::size_t i = 0; i < n_bodies; ++i) {
    if (state_[i].q_f.size() == 0) continue;
    mid_[i].q_f = 0.5 * (state_[i].q_f + next_[i].q_f);
    mid_[i].qd_f = state_[i].qd_f + (0.5 * h) * acc_[i].qdd_f;
  }

  // 2. W_{n+1} ← root of r(W) = J W − exp(−Θ̃)(J W_n + h R_nᵀ Γ_{n+½}), Θ = (h/2)(W_n + W).
  const NewtonOutcome newton = solve_balance(t_n, h);
  if (!newton.finite) return {false, detail::non_finite_failure("C1", t_n, h)};
  if (!newton.converged) {
    return {false, detail::newton_failure("C1", t_n, h, newton.relative_residual, newton.iterations,
                                          newton.worst_body)};
  }

  // 3. Attitude at t_{n+1} and the Newmark acceleration.
  for (std::size_t i = 0; i < n_bodies; ++i) {
    const core::BodyState& s = state_[i];
    core::BodyState& s1 = next_[i];
    if (model_.body(static_cast<int>(i)).is_prescribed()) continue;  // the law's attitude
    // R_{n+1} ← R_n exp(Θ̃)   (θ_{n+1} = θ_n ⊗ exp(Θ), renormalized)
    const Vector3d theta = detail::c1_increment(s.w_WB_B, s1.w_WB_B, h);
    s1.theta_WB = rotation::quaternion_multiply(s.theta_WB, rotation::exp_quaternion(theta));
    detail::renormalize_unit_product(s1.theta_WB);
    // A_{n+1} ← (W_{n+1} − W_n)/h
    acc_next_[i].alpha_WB_B = (s1.w_WB_B - s.w_WB_B) / h;
    // v ← v_n + h a_n   (predictor for the end evaluation)
    if (model_.body(static_cast<int>(i)).is_free()) s1.v_WBr = s.v_WBr + h * acc_[i].a_WBr;
  }

  // 4. Translation and modes: a_{n+1} from the loads at the new configuration (central
  //    differences).
  std::optional<core::Loads> end_loads;
  if (has_free_body_) {
    end_loads = model_.compute_wrenches(core::LoadContext{t_np1, t_n + 0.5 * h}, next_, ws_);
    ++evaluations_;
  }
  for (std::size_t i = 0; i < n_bodies; ++i) {
    // a_{n+1} ← f_{n+1}/m,  v_{n+1} ← v_n + ½ h (a_n + a_{n+1})
    detail::update_translation(model_.body(static_cast<int>(i)), ws_.wrenches[i], state_[i],
                               acc_[i], h, next_[i], acc_next_[i]);
  }
  // 5. Modes: q̈_{n+1} from the LTE modal equation, q̇_{n+1} ← q̇_n + ½ h (q̈_n + q̈_{n+1}).
  detail::update_modes(model_, end_loads ? &*end_loads : nullptr, t_np1, ws_, state_, acc_, h,
                       next_, acc_next_);

  if (!detail::all_finite(next_)) return {false, detail::non_finite_failure("C1", t_n, h)};
  wear_.correct(core::LoadContext{t_np1, t_n + 0.5 * h}, state_, h, next_, ws_);
  std::swap(state_, next_);
  std::swap(acc_, acc_next_);
  wear_.accept();
  time_ = t_np1;
  restart_pending_ = false;
  newton_iterations_ += newton.iterations;
  max_newton_iterations_ = std::max(max_newton_iterations_, newton.iterations);
  ++steps_;
  return {};
}

}  // namespace flexref::lie
