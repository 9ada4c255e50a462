#include "lie/nmb.hpp"

#include <Eigen/LU>  // Matrix3d::inverse
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <utility>

#include "lie/nmb_newton.hpp"
#include "lie/scheme_support.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::lie {

using Eigen::Matrix3d;
using Eigen::Vector3d;

NmbStepper::NmbStepper(const core::Model& model)
    : model_(model),
      state_(model.initial_state()),
      next_(state_),
      acc_(model.make_accelerations()),
      acc_next_(model.make_accelerations()),
      ws_(model.make_workspace()),
      wear_(model) {
  detail::require_hybrid_scheme_model(model, "nmb");
}

void NmbStepper::initialize(double t0, const core::State& state) {
  if (state.size() != state_.size()) {
    throw std::invalid_argument("nmb: the state has a different number of bodies than the model");
  }
  time_ = t0;
  state_ = state;
  next_ = state;
  // t_segment = t0 selects the branch on the right of t0; the first step re-evaluates on its
  // own segment [t0, t0 + h).
  model_.compute_accelerations(core::LoadContext{t0, t0}, state_, ws_, acc_);
  wear_.start(core::LoadContext{t0, t0}, state_, ws_);
  restart_pending_ = true;
  newton_iterations_ = 0;
  max_newton_iterations_ = 0;
  steps_ = 0;
}

void NmbStepper::restart(double h) {
  // a_n = f_n/m,  A_n = J⁻¹ (T_n − W_n × J W_n)   (Euler, right limit at t_n)
  model_.compute_accelerations(core::LoadContext{time_, time_ + 0.5 * h}, state_, ws_, acc_);
  wear_.start(core::LoadContext{time_, time_ + 0.5 * h}, state_, ws_);
}

StepStatus NmbStepper::step(double h) {
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

  // 3. Accelerations and velocities at t_{n+1}.
  int step_max_iterations = 0;
  long step_iterations = 0;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const core::Body& body = model_.body(static_cast<int>(i));
    const core::BodyState& s = state_[i];
    core::BodyState& s1 = next_[i];
    // a_{n+1} ← f_{n+1}/m,  v_{n+1} ← v_n + ½ h (a_n + a_{n+1})
    detail::update_translation(body, ws_.wrenches[i], s, acc_[i], h, s1, acc_next_[i]);
    if (body.is_prescribed()) continue;  // attitude and W follow the law
    const Matrix3d& J = body.I_Br_B();
    const Vector3d& W_n = s.w_WB_B;
    const Vector3d& A_n = acc_[i].alpha_WB_B;
    // T_{n+1} ← R_{n+1}ᵀ Γ_{n+1}
    const Vector3d T_np1 = ws_.kinematics[i].R_WB.transpose() * ws_.wrenches[i].tau_Br_W;
    // Newton on f(A) = J A + W(A) × J W(A) − T_{n+1} = 0, from A ← A_n.
    Vector3d& A = acc_next_[i].alpha_WB_B;
    A = A_n;
    int iterations = 0;  // Jacobian solves
    double previous_relative = std::numeric_limits<double>::infinity();
    for (;;) {
      // f ← J A + W × J W − T_{n+1},  W = W_n + (h/2)(A_n + A);  K ← J + (h/2)(W̃ J − (J W)~)
      const detail::NmbLinearization f = detail::nmb_linearize(J, T_np1, W_n, A_n, A, h);
      const double relative_residual =
          detail::max_abs(f.residual) / (f.scale > 0.0 ? f.scale : 1.0);
      if (!std::isfinite(relative_residual)) {
        return {false, detail::non_finite_failure("NMB", t_n, h)};
      }
      // A ← A − K⁻¹ f   (also after the test has passed: the correction then costs nothing
      // but a 3×3 solve and removes the remainder ≤ 1e-14 that would otherwise bias every
      // step the same way)
      A -= f.jacobian.inverse() * f.residual;
      ++iterations;
      if (relative_residual <= detail::kNewtonTolerance ||
          detail::newton_stagnated(relative_residual, previous_relative)) {
        break;
      }
      previous_relative = relative_residual;
      if (iterations == kMaxNewtonIterations) {
        return {false, detail::newton_failure("NMB", t_n, h, relative_residual, iterations,
                                              static_cast<int>(i))};
      }
    }
    step_iterations += iterations;
    step_max_iterations = std::max(step_max_iterations, iterations);
    // W_{n+1} ← W_n + (h/2)(A_n + A_{n+1})
    s1.w_WB_B = detail::nmb_velocity(W_n, A_n, A, h);
  }
  // 4. Modes: q̈_{n+1} from the LTE modal equation, q̇_{n+1} ← q̇_n + ½ h (q̈_n + q̈_{n+1}).
  detail::update_modes(model_, &end_loads, t_np1, ws_, state_, acc_, h, next_, acc_next_);

  if (!detail::all_finite(next_)) return {false, detail::non_finite_failure("NMB", t_n, h)};
  wear_.correct(core::LoadContext{t_np1, t_n + 0.5 * h}, state_, h, next_, ws_);
  std::swap(state_, next_);
  std::swap(acc_, acc_next_);
  wear_.accept();
  time_ = t_np1;
  restart_pending_ = false;
  newton_iterations_ += step_iterations;
  max_newton_iterations_ = std::max(max_newton_iterations_, step_max_iterations);
  ++steps_;
  return {};
}

}  // namespace flexref::lie
