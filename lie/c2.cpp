#include "lie/c2.hpp"

#include <cstddef>
#include <stdexcept>
#include <utility>

#include "lie/scheme_support.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::lie {

using Eigen::Matrix3d;
using Eigen::Vector3d;

C2Stepper::C2Stepper(const core::Model& model)
    : model_(model),
      state_(model.initial_state()),
      next_(state_),
      acc_(model.make_accelerations()),
      acc_next_(model.make_accelerations()),
      torque_W_(state_.size(), Vector3d::Zero()),
      torque_next_W_(state_.size(), Vector3d::Zero()),
      momentum_W_(state_.size(), Vector3d::Zero()),
      momentum_next_W_(state_.size(), Vector3d::Zero()),
      ws_(model.make_workspace()),
      wear_(model) {
  detail::require_hybrid_scheme_model(model, "c2");
}

void C2Stepper::initialize(double t0, const core::State& state) {
  if (state.size() != state_.size()) {
    throw std::invalid_argument("c2: the state has a different number of bodies than the model");
  }
  time_ = t0;
  state_ = state;
  next_ = state;
  // The step length is not known yet: evaluate on the right of t0 (t_segment = t0 is inside
  // [t0, t0 + h) for every half-open time law); the first step re-evaluates on its own segment.
  model_.compute_accelerations(core::LoadContext{t0, t0}, state_, ws_, acc_);
  wear_.start(core::LoadContext{t0, t0}, state_, ws_);
  for (std::size_t i = 0; i < state_.size(); ++i) {
    torque_W_[i] = ws_.wrenches[i].tau_Br_W;
    // π_0 = R_0 J W_0, then carried by the scheme (it is the scheme's primary unknown).
    momentum_W_[i] =
        ws_.kinematics[i].R_WB * (model_.body(static_cast<int>(i)).I_Br_B() * state_[i].w_WB_B);
  }
  restart_pending_ = true;
}

void C2Stepper::restart(double h) {
  const core::LoadContext start{time_, time_ + 0.5 * h};
  wear_.start(start, state_, ws_);
  if (restart_pending_) {
    // First step: a_0 = f_0/m, A_0 = J⁻¹ (R_0ᵀ Γ_0 − W_0 × J W_0)   (Euler, right limit at t0)
    model_.compute_accelerations(start, state_, ws_, acc_);
    for (std::size_t i = 0; i < state_.size(); ++i) torque_W_[i] = ws_.wrenches[i].tau_Br_W;
    return;
  }
  // Step from a load discontinuity: Γ_n and a_n are re-evaluated (right limits). A_n is the
  // scheme's backward difference (W_n − W_{n−1})/h, not a load: it keeps its value and takes
  // the jump of the acceleration the load jump implies, A_n ← A_n + J⁻¹ R_nᵀ (Γ_n⁺ − Γ_n⁻)
  // (zero for a body whose loads do not jump).
  const core::Loads loads = model_.compute_wrenches(start, state_, ws_);
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const core::Body& body = model_.body(static_cast<int>(i));
    const Vector3d& torque_plus_W = ws_.wrenches[i].tau_Br_W;
    acc_[i].alpha_WB_B += body.I_Br_B_inverse() *
                          (ws_.kinematics[i].R_WB.transpose() * (torque_plus_W - torque_W_[i]));
    torque_W_[i] = torque_plus_W;
    acc_[i].a_WBr = body.is_free() ? Vector3d(ws_.wrenches[i].f_W / body.mass()) : Vector3d::Zero();
    // The modal accelerations are loads' consequences: right limits from the new loads.
    if (body.is_flexible()) {
      model_.modal_accelerations(static_cast<int>(i), loads, acc_[i].a_WBr, acc_[i].alpha_WB_B, ws_,
                                 acc_[i].qdd_f);
    }
  }
}

StepStatus C2Stepper::step(double h) {
  const double t_n = time_;
  const double t_np1 = t_n + h;
  if (restart_pending_ || detail::starts_on_discontinuity(model_.discontinuities(), t_n, h)) {
    restart(h);
  }
  // The worn depths the step's loads see: h_n + Δt ḣ_n.
  wear_.predict(state_, h, next_);

  // 1. Configuration at t_{n+1}, explicit (Θ ← h W_n + ½ h² A_n, x_{n+1} ← x_n + h v_n + ½ h² a_n).
  detail::predict_configuration(model_, state_, acc_, h, next_);
  // q_{n+1} ← q_n + h q̇_n + ½ h² q̈_n;  prescribed bodies: their law at t_{n+1}.
  detail::predict_modes(model_, state_, acc_, h, t_np1, next_);

  // 2. The one force evaluation: f_{n+1}, Γ_{n+1} at the new configuration.
  const core::Loads end_loads =
      model_.compute_wrenches(core::LoadContext{t_np1, t_n + 0.5 * h}, next_, ws_);

  // 3. Velocities at t_{n+1}.
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const core::Body& body = model_.body(static_cast<int>(i));
    const core::BodyState& s = state_[i];
    core::BodyState& s1 = next_[i];
    const Matrix3d& R_np1 = ws_.kinematics[i].R_WB;
    // a_{n+1} ← f_{n+1}/m,  v_{n+1} ← v_n + ½ h (a_n + a_{n+1})
    detail::update_translation(body, ws_.wrenches[i], s, acc_[i], h, s1, acc_next_[i]);
    torque_next_W_[i] = ws_.wrenches[i].tau_Br_W;
    if (body.is_prescribed()) continue;  // attitude and W follow the law
    // π_{n+1} ← R_n J W_n + (h/2)(Γ_n + Γ_{n+1})
    //          (π_n = R_n J W_n is carried from the previous step)
    momentum_next_W_[i] = momentum_W_[i] + (0.5 * h) * (torque_W_[i] + torque_next_W_[i]);
    // W_{n+1} ← J⁻¹ R_{n+1}ᵀ π_{n+1}
    s1.w_WB_B = body.I_Br_B_inverse() * (R_np1.transpose() * momentum_next_W_[i]);
    // A_{n+1} ← (W_{n+1} − W_n)/h
    acc_next_[i].alpha_WB_B = (s1.w_WB_B - s.w_WB_B) / h;
  }
  // 4. Modes: q̈_{n+1} from the LTE modal equation, q̇_{n+1} ← q̇_n + ½ h (q̈_n + q̈_{n+1}).
  detail::update_modes(model_, &end_loads, t_np1, ws_, state_, acc_, h, next_, acc_next_);

  if (!detail::all_finite(next_)) return {false, detail::non_finite_failure("C2", t_n, h)};
  wear_.correct(core::LoadContext{t_np1, t_n + 0.5 * h}, state_, h, next_, ws_);
  std::swap(state_, next_);
  std::swap(acc_, acc_next_);
  wear_.accept();
  std::swap(torque_W_, torque_next_W_);
  std::swap(momentum_W_, momentum_next_W_);
  time_ = t_np1;
  restart_pending_ = false;
  return {};
}

}  // namespace flexref::lie
