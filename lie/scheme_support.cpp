#include "lie/scheme_support.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/prescribed_motion.hpp"

namespace flexref::lie::detail {

bool starts_on_discontinuity(std::span<const double> discontinuities, double t_n, double h) {
  const double tolerance = 1e-9 * std::max(h, std::abs(t_n));
  const auto it = std::lower_bound(discontinuities.begin(), discontinuities.end(), t_n - tolerance);
  return it != discontinuities.end() && *it <= t_n + tolerance;
}

void predict_configuration(const core::Model& model, const core::State& state,
                           const core::Accelerations& acc, double h, core::State& next) {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const core::BodyState& s = state[i];
    core::BodyState& s1 = next[i];
    const Eigen::Vector3d& a_n = acc[i].a_WBr;
    const Eigen::Vector3d& A_n = acc[i].alpha_WB_B;
    if (model.body(static_cast<int>(i)).is_free()) {
      // x_{n+1} ← x_n + h v_n + ½ h² a_n
      s1.p_WBr = s.p_WBr + h * s.v_WBr + (0.5 * h * h) * a_n;
      // v ← v_n + h a_n   (predictor, seen only by velocity-dependent loads)
      s1.v_WBr = s.v_WBr + h * a_n;
    } else {
      s1.p_WBr = s.p_WBr;
      s1.v_WBr.setZero();
    }
    // Θ ← h W_n + ½ h² A_n
    const Eigen::Vector3d theta = h * s.w_WB_B + (0.5 * h * h) * A_n;
    // R_{n+1} ← R_n exp(Θ̃)   (θ_{n+1} = θ_n ⊗ exp(Θ), renormalized)
    s1.theta_WB = rotation::quaternion_multiply(s.theta_WB, rotation::exp_quaternion(theta));
    renormalize_unit_product(s1.theta_WB);
    // W ← W_n + h A_n   (predictor, seen only by velocity-dependent loads)
    s1.w_WB_B = s.w_WB_B + h * A_n;
  }
}

void update_translation(const core::Body& body, const core::Wrench& wrench,
                        const core::BodyState& state, const core::BodyAcceleration& acc, double h,
                        core::BodyState& next, core::BodyAcceleration& acc_next) {
  if (body.is_free()) {
    // a_{n+1} ← f_{n+1}/m
    acc_next.a_WBr = wrench.f_W / body.mass();
    // v_{n+1} ← v_n + ½ h (a_n + a_{n+1})
    next.v_WBr = state.v_WBr + (0.5 * h) * (acc.a_WBr + acc_next.a_WBr);
  } else {
    acc_next.a_WBr.setZero();
  }
}

void predict_modes(const core::Model& model, const core::State& state,
                   const core::Accelerations& acc, double h, double t_np1, core::State& next) {
  if (!model.has_flexible_bodies()) {
    model.apply_prescribed_motion(t_np1, next);
    return;
  }
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state[i].q_f.size() == 0) continue;
    // q_{n+1} ← q_n + h q̇_n + ½ h² q̈_n;  q̇ ← q̇_n + h q̈_n (predictor)
    next[i].q_f = state[i].q_f + h * state[i].qd_f + (0.5 * h * h) * acc[i].qdd_f;
    next[i].qd_f = state[i].qd_f + h * acc[i].qdd_f;
  }
  model.apply_prescribed_motion(t_np1, next);
}

void update_modes(const core::Model& model, const core::Loads* end_loads, double t_np1,
                  core::Workspace& ws, const core::State& state, const core::Accelerations& acc,
                  double h, core::State& next, core::Accelerations& acc_next) {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const core::Body& body = model.body(static_cast<int>(i));
    if (body.is_prescribed()) {
      const core::RigidBodyDescription& d = body.description();
      acc_next[i].alpha_WB_B =
          core::prescribed_attitude(d.prescribed, d.initial.theta_WB, t_np1).alpha_WB_B;
    }
    if (!body.is_flexible()) continue;
    if (end_loads == nullptr || &end_loads->state() != &next) {
      throw std::logic_error("update_modes: the loads at the new configuration are needed");
    }
    core::BodyState& s1 = next[i];
    // α̅_{n+1} ← J⁻¹ (R_{n+1}ᵀ Γ_{n+1} − W_{n+1} × J W_{n+1})   (not used for prescribed bodies)
    Eigen::Vector3d alpha = Eigen::Vector3d::Zero();
    if (!body.is_prescribed()) {
      const Eigen::Matrix3d& J = body.I_Br_B();
      const Eigen::Vector3d T_B = ws.kinematics[i].R_WB.transpose() * ws.wrenches[i].tau_Br_W;
      alpha = body.I_Br_B_inverse() * (T_B - s1.w_WB_B.cross(J * s1.w_WB_B));
    }
    // q̈_{n+1} from the modal equation (q_{n+1}, predicted q̇, W_{n+1}, a_{n+1}, α̅_{n+1})
    model.modal_accelerations(static_cast<int>(i), *end_loads, acc_next[i].a_WBr, alpha, ws,
                              acc_next[i].qdd_f);
    // q̇_{n+1} ← q̇_n + ½ h (q̈_n + q̈_{n+1})
    s1.qd_f = state[i].qd_f + (0.5 * h) * (acc[i].qdd_f + acc_next[i].qdd_f);
  }
}

void require_hybrid_scheme_model(const core::Model& model, const char* scheme) {
  if (model.has_constraints()) {
    const core::ConstraintEquations& joints = *model.constraints();
    throw std::invalid_argument(
        std::string(scheme) + ": the scene has the ideal joint '" + joints.joint_name(0) +
        "'; C1, C2 and NMB step unconstrained bodies only (their rotation updates have no "
        "multipliers). Step it with --scheme genalpha (the Lie-group generalized-alpha, index 3: "
        "docs/schemes.md), compute a reference (flexref reference: CVODE, ARKODE, Odeint on the "
        "index-1 form, IDA on the stabilized index-2 form), or model the joint as a bushing "
        "(model = \"bushing\") to run these schemes (docs/joints.md)");
  }
  if (model.has_flexible_bodies() && model.formulation() != core::FlexibleFormulation::kLte) {
    throw std::invalid_argument(
        std::string(scheme) +
        ": the hybrid schemes integrate the LTE model of flexible bodies (rigid motion first, "
        "then the modes by central differences, as in the paper); use the LTE formulation "
        "(--model lte) or a reference solver for the coupled model");
  }
}

bool all_finite(const core::State& state) {
  // One sum instead of 13 tests per body: NaN and ±inf propagate through a sum. The sum of
  // finite values can overflow only for entries near 1e308, which are reported as non-finite
  // too — a state that large has already failed.
  double sum = 0.0;
  for (const core::BodyState& s : state) {
    sum += s.p_WBr.sum() + s.theta_WB.sum() + s.v_WBr.sum() + s.w_WB_B.sum() + s.q_f.sum() +
           s.qd_f.sum();
  }
  return std::isfinite(sum) && sum == sum;
}

std::string newton_failure(const char* scheme, double t_n, double h, double relative_residual,
                           int iterations, int body) {
  std::ostringstream out;
  out.precision(17);
  out << scheme << " Newton did not converge at t = " << t_n << " (step h = " << h << "), residual "
      << relative_residual << " (relative, tolerance " << kNewtonTolerance << ") after "
      << iterations << " iterations, body " << body;
  return out.str();
}

std::string non_finite_failure(const char* scheme, double t_n, double h) {
  std::ostringstream out;
  out.precision(17);
  out << scheme << ": non-finite state in the step from t = " << t_n << " with h = " << h;
  return out.str();
}

}  // namespace flexref::lie::detail
