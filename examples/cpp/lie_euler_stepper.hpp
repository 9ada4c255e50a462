#pragma once
/// \file lie_euler_stepper.hpp
/// A user's own integrator written against flexref's installed headers: the explicit
/// Lie–Euler method, first order, for every body of a model (rigid, pivot, flexible modes):
///   θ_{n+1} = θ_n ⊗ exp(h W_n),   W_{n+1} = W_n + h α_n,
///   x_{n+1} = x_n + h v_n,         v_{n+1} = v_n + h a_n,
///   q_{n+1} = q_n + h q̇_n,         q̇_{n+1} = q̇_n + h q̈_n,
/// with the accelerations of the model at (t_n, state_n). It implements flexref::lie::Stepper,
/// so once registered (register_lie_euler) every flexref study runs it by name.
#include <cmath>
#include <flexref/core/model.hpp>
#include <flexref/lie/method_registry.hpp>
#include <flexref/lie/stepper.hpp>
#include <flexref/rotation/euler_parameters.hpp>
#include <memory>
#include <sstream>
#include <string>

namespace user {

class LieEulerStepper final : public flexref::lie::Stepper {
 public:
  explicit LieEulerStepper(const flexref::core::Model& model)
      : model_(model),
        next_(model.initial_state()),
        acc_(model.make_accelerations()),
        ws_(model.make_workspace()) {}

  std::string_view name() const override { return "lie_euler"; }
  int order() const override { return 1; }
  double force_evaluations_per_step() const override { return 1.0; }

  void initialize(double t0, const flexref::core::State& state) override {
    time_ = t0;
    state_ = state;
    next_ = state;
  }

  flexref::lie::StepStatus step(double h) override {
    // Loads of the segment the step lies in (the driver never lets a step straddle a switch).
    model_.compute_accelerations(flexref::core::LoadContext{time_, time_ + 0.5 * h}, state_, ws_,
                                 acc_);
    for (std::size_t i = 0; i < state_.size(); ++i) {
      const flexref::core::BodyState& s = state_[i];
      const flexref::core::BodyAcceleration& a = acc_[i];
      if (!a.a_WBr.allFinite() || !a.alpha_WB_B.allFinite() ||
          (a.qdd_f.size() > 0 && !a.qdd_f.allFinite())) {
        std::ostringstream why;
        why.precision(17);
        why << "non-finite acceleration of body " << i << " at t = " << time_;
        return {false, why.str()};  // state and time untouched
      }
      flexref::core::BodyState& n = next_[i];
      n.p_WBr = s.p_WBr + h * s.v_WBr;                      // x_{n+1} = x_n + h v_n
      n.v_WBr = s.v_WBr + h * a.a_WBr;                      // v_{n+1} = v_n + h a_n
      n.theta_WB = flexref::rotation::quaternion_multiply(  // θ_{n+1} = θ_n ⊗ exp(h W_n)
          s.theta_WB, flexref::rotation::exp_quaternion(h * s.w_WB_B));
      n.theta_WB.normalize();
      n.w_WB_B = s.w_WB_B + h * a.alpha_WB_B;  // W_{n+1} = W_n + h α_n
      if (s.q_f.size() > 0) {
        n.q_f = s.q_f + h * s.qd_f;     // q_{n+1} = q_n + h q̇_n
        n.qd_f = s.qd_f + h * a.qdd_f;  // q̇_{n+1} = q̇_n + h q̈_n
      }
    }
    model_.apply_prescribed_motion(time_ + h, next_);
    std::swap(state_, next_);
    time_ += h;
    return {};
  }

  double time() const override { return time_; }
  const flexref::core::State& state() const override { return state_; }

 private:
  const flexref::core::Model& model_;
  double time_ = 0.0;
  flexref::core::State state_;
  flexref::core::State next_;
  flexref::core::Accelerations acc_;
  flexref::core::Workspace ws_;
};

/// Registers "lie_euler" (claimed order 1) with flexref's method registry; call once.
inline void register_lie_euler() {
  flexref::lie::register_method(
      {"lie_euler", 1, "explicit Lie-Euler (user example)",
       [](const flexref::core::Model& m, const flexref::lie::MethodOptions&) {
         return std::make_unique<LieEulerStepper>(m);
       }});
}

}  // namespace user
