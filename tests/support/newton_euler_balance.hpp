#pragma once
/// \file newton_euler_balance.hpp
/// Each rigid body's Newton–Euler balance at every row of a jointed trajectory's table, with the
/// joint reactions as the table writes them (the `J.fx … J.tz` columns, docs/joints.md) and the
/// accelerations taken from the output's velocities by finite differences: independent of the
/// constrained solve that produced the reactions. For a free rigid body i (Br = its centre of
/// mass C_i; Newton–Euler about C_i, docs/design/model.md):
///
///   m_i a_C = f_applied + Σ_j s_ij f_j,
///   A (I_C α̅ + ω̄ × I_C ω̄) = τ_applied,C + Σ_j s_ij (τ_j + (p_Pj − p_C) × f_j),
///
/// where joint j reports (f_j, τ_j), the force and the torque about its point P_j on its first
/// body (world), s_ij = +1 when body i is the joint's first end and −1 when it is the second: an
/// ideal joint's rows are invariant under a rigid motion of both its ends together, so the
/// virtual power of its generalized force −Jᵀλ on such a motion vanishes — the wrench on the
/// second body is the opposite of the first's, about the same point P_j (Newton's third law in
/// its strong form). The applied loads are the force elements' (Model::compute_wrenches: force
/// and torque about Br, world).
///
/// Accelerations: a_C and α̅ by fourth-order differences of v_WBr and ω̄ (the body-frame
/// derivative of ω̄ is α̅, since ω̄ × ω̄ = 0) over a uniform output grid of step h — central
/// (f₋₂ − 8f₋₁ + 8f₁ − f₂)/(12h) inside, truncation h⁴ f⁽⁵⁾/30; the one-sided five-point
/// formulas on the first and last two rows, truncation ≤ h⁴ f⁽⁵⁾/5 (Fornberg, Math. Comp. 51
/// (1988), table 1). For a motion of fastest rate ω the relative truncation is ≲ (hω)⁴/5, and a
/// velocity noise ε v (the solver's) adds ≲ 10.7 ε/(hω) at the ends (the one-sided weights'
/// Σ|c|/12 = 10.7), 1.5 ε/(hω) inside. Both are the caller's to keep below its tolerance.
/// Header-only; needs flexref::constraint and flexref::trajectory.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "constraint/ideal_joints.hpp"
#include "core/model.hpp"
#include "core/state.hpp"
#include "rotation/euler_parameters.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::testing {

/// The largest relative residuals of the balance over the rows and bodies, and where.
struct NewtonEulerResidual {
  /// |m a − f_applied − Σ s f| / the body's largest term over the run
  double force = 0.0;
  /// The same for the torque about the centre of mass, against the body's largest torque term
  /// or its largest force term times the mechanism's largest joint arm, whichever is larger
  double torque = 0.0;
  std::string force_at;
  std::string torque_at;
  std::size_t rows = 0;  ///< rows checked (every row of the table)
};

namespace detail {

/// d/dt of samples f(t_k) at row k of a uniform grid of step h, fourth order (weights of the
/// five-point stencil that fits the grid's ends).
template <typename Sample>
Eigen::Vector3d five_point_derivative(const Sample& f, std::size_t k, std::size_t n, double h) {
  // Offsets of the stencil from k and their weights ×12h (Fornberg 1988, table 1).
  static constexpr std::array<double, 5> kCentral = {1.0, -8.0, 0.0, 8.0, -1.0};
  static constexpr std::array<double, 5> kForward0 = {-25.0, 48.0, -36.0, 16.0, -3.0};
  static constexpr std::array<double, 5> kForward1 = {-3.0, -10.0, 18.0, -6.0, 1.0};
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  const auto apply = [&](const std::array<double, 5>& w, std::size_t first, double sign) {
    for (std::size_t j = 0; j < 5; ++j) d += sign * w[j] * f(first + j);
  };
  if (k >= 2 && k + 2 < n) {
    apply(kCentral, k - 2, 1.0);
  } else if (k < 2) {
    apply(k == 0 ? kForward0 : kForward1, 0, 1.0);  // stencils starting at row 0
  } else {
    // The mirror images at the end: f'(t) of the reversed samples, with the sign changed.
    const std::array<double, 5>& w = k + 1 == n ? kForward0 : kForward1;
    for (std::size_t j = 0; j < 5; ++j) d -= w[j] * f(n - 1 - j);
  }
  return d / (12.0 * h);
}

}  // namespace detail

/// The balance at every row of `table` (tabulated from `trajectory` of `model`, whose bodies must
/// be free rigid bodies and whose joints' ends must be body points, not nodes). The output times
/// must be uniform (to 1e-9 of the step) and at least five.
inline NewtonEulerResidual newton_euler_residual(const core::Model& model,
                                                 const core::Trajectory& trajectory,
                                                 const trajectory::TrajectoryTable& table) {
  const auto* joints = dynamic_cast<const constraint::IdealJoints*>(model.constraints());
  if (joints == nullptr) throw std::invalid_argument("newton_euler_residual: no ideal joints");
  const std::size_t n = trajectory.times.size();
  if (n < 5 || table.size() != n) throw std::invalid_argument("newton_euler_residual: rows");
  const double h = (trajectory.times.back() - trajectory.times.front()) / double(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (std::abs(trajectory.times[k + 1] - trajectory.times[k] - h) > 1e-9 * h) {
      throw std::invalid_argument("newton_euler_residual: the output grid is not uniform");
    }
  }
  for (const core::Body& b : model.bodies()) {
    if (!b.is_free() || b.mode_count() > 0) {
      throw std::invalid_argument("newton_euler_residual: body " + b.description().name +
                                  " is not a free rigid body");
    }
  }
  const std::vector<constraint::IdealJointSpec>& specs = joints->joints();
  std::vector<int> first_column;
  for (const constraint::IdealJointSpec& j : specs) {
    if (j.a.node >= 0 || j.b.node >= 0) {
      throw std::invalid_argument("newton_euler_residual: joint " + j.name + " at a node");
    }
    const int c = table.column(j.name + ".fx");
    const std::array<const char*, 5> rest = {".fy", ".fz", ".tx", ".ty", ".tz"};
    for (std::size_t r = 0; r < rest.size(); ++r) {
      if (table.column(j.name + rest[r]) != c + 1 + static_cast<int>(r)) {
        throw std::invalid_argument("newton_euler_residual: columns of joint " + j.name);
      }
    }
    first_column.push_back(c);
  }
  // Residuals per row and body, and each body's largest term over the run: the differences'
  // errors are relative to a body's motion as a whole (a body momentarily at rest still has
  // the truncation of its later rows), and a row where every term vanishes would otherwise
  // measure round-off against round-off.
  const auto bodies = static_cast<std::size_t>(model.num_bodies());
  std::vector<Eigen::Vector3d> f_res(n * bodies), tau_res(n * bodies);
  std::vector<double> f_scale(bodies, 0.0), tau_scale(bodies, 0.0);
  double arm = 0.0;  // the mechanism's largest joint arm |p_P − p_C| (m)
  core::Workspace ws = model.make_workspace();
  for (std::size_t k = 0; k < n; ++k) {
    const double t = trajectory.times[k];
    const core::State& state = trajectory.states[k];
    model.compute_wrenches(core::LoadContext{t, t}, state, ws);
    const std::vector<double>& row = table.rows[k];
    for (std::size_t bi = 0; bi < bodies; ++bi) {
      const int i = static_cast<int>(bi);
      const core::Body& body = model.body(i);
      const core::BodyState& s = state[bi];
      const Eigen::Vector3d a_WC = detail::five_point_derivative(
          [&](std::size_t m) { return trajectory.states[m][bi].v_WBr; }, k, n, h);
      const Eigen::Vector3d alpha_B = detail::five_point_derivative(
          [&](std::size_t m) { return trajectory.states[m][bi].w_WB_B; }, k, n, h);
      const Eigen::Matrix3d R_WB = rotation::rotation_matrix(s.theta_WB);
      const Eigen::Matrix3d& I_B = body.I_Br_B();
      const Eigen::Vector3d w_B = s.w_WB_B;
      const Eigen::Vector3d f_inertia = body.mass() * a_WC;
      const Eigen::Vector3d tau_inertia = R_WB * (I_B * alpha_B + w_B.cross(I_B * w_B));
      const core::Wrench& applied = ws.wrenches[bi];
      Eigen::Vector3d& fr = f_res[k * bodies + bi];
      Eigen::Vector3d& tr = tau_res[k * bodies + bi];
      fr = f_inertia - applied.f_W;
      tr = tau_inertia - applied.tau_Br_W;
      f_scale[bi] = std::max({f_scale[bi], f_inertia.norm(), applied.f_W.norm()});
      tau_scale[bi] = std::max({tau_scale[bi], tau_inertia.norm(), applied.tau_Br_W.norm()});
      for (std::size_t j = 0; j < specs.size(); ++j) {
        const constraint::IdealJointSpec& spec = specs[j];
        const double sign = spec.a.body == i ? 1.0 : spec.b.body == i ? -1.0 : 0.0;
        if (sign == 0.0) continue;
        const auto c = static_cast<std::size_t>(first_column[j]);
        const Eigen::Vector3d f(row[c], row[c + 1], row[c + 2]);
        const Eigen::Vector3d tau_P(row[c + 3], row[c + 4], row[c + 5]);
        const auto a = static_cast<std::size_t>(spec.a.body);
        const Eigen::Vector3d r_CP = model.p_WP(spec.a.body, state[a], spec.a.p_BoP_B) - s.p_WBr;
        const Eigen::Vector3d arm_f = r_CP.cross(f);
        fr -= sign * f;
        tr -= sign * (tau_P + arm_f);
        f_scale[bi] = std::max(f_scale[bi], f.norm());
        tau_scale[bi] = std::max({tau_scale[bi], tau_P.norm(), arm_f.norm()});
        arm = std::max(arm, r_CP.norm());
      }
    }
  }
  NewtonEulerResidual out;
  out.rows = n;
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t bi = 0; bi < bodies; ++bi) {
      // A torque is measured against the body's torques and against its forces at the
      // mechanism's arm: a force's error δf at that arm is a torque error δf × arm.
      const double fs = f_scale[bi];
      const double ts = std::max(tau_scale[bi], fs * arm);
      const double rf = f_res[k * bodies + bi].norm() / (fs > 0.0 ? fs : 1.0);
      const double rt = tau_res[k * bodies + bi].norm() / (ts > 0.0 ? ts : 1.0);
      const auto where = [&](double r, double scale) {
        std::ostringstream o;
        o << "body " << model.body(static_cast<int>(bi)).description().name
          << " at t = " << trajectory.times[k] << " (row " << k << "): " << r << " of " << scale;
        return o.str();
      };
      if (rf >= out.force) {
        out.force = rf;
        out.force_at = where(rf, fs);
      }
      if (rt >= out.torque) {
        out.torque = rt;
        out.torque_at = where(rt, ts);
      }
    }
  }
  return out;
}

}  // namespace flexref::testing
