#pragma once
/// \file scheme_support.hpp
/// Helpers shared by the C1, C2 and NMB steppers (not part of the public interface): where a
/// step starts on a load discontinuity, finiteness checks, the Newton tolerance, and the
/// failure messages (built only on failure, so a successful step allocates nothing).
#include <Eigen/Core>
#include <span>
#include <string>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::lie::detail {

/// Relative Newton tolerance of C1 and NMB: a residual is converged when every component is
/// ≤ kNewtonTolerance · (size of the terms it is the sum of). Evaluating a residual costs a
/// handful of rounded operations per component (a rotation, two matrix-vector products and
/// a difference), so its round-off floor is ≈ 5 ε ≈ 1e-15 of that size: 1e-14 is reachable,
/// yet leaves a relative error in W_{n+1} or A_{n+1} below the local truncation error of any
/// step a study uses (O(h³) ≥ 1e-14 for h ≥ 1e-4 and rates O(1)).
inline constexpr double kNewtonTolerance = 1e-14;
/// Round-off floor accepted when a Newton iteration stagnates. Loads whose Jacobian is known
/// only to forward-difference accuracy (C1 on friction and dampers) or whose net torque is
/// the small difference of large contributions leave a residual floor above kNewtonTolerance.
/// An iterate whose relative residual is ≤ kNewtonStagnationFloor and decreased by less than
/// half in the last iteration is at that floor (Newton converges quadratically, quasi-Newton
/// at least linearly with ratio < ½ near the root) and is accepted. Smooth scenes converge to
/// kNewtonTolerance before ever stagnating (their order tests are unchanged); 1e-10 in W_{n+1}
/// is far below the truncation error of the contact scenes' steps (docs/contact_results.md).
inline constexpr double kNewtonStagnationFloor = 1e-10;
/// True when a Newton iteration has stagnated at its round-off floor (see above).
inline bool newton_stagnated(double relative_residual, double previous_relative_residual) {
  return relative_residual <= kNewtonStagnationFloor &&
         relative_residual > 0.5 * previous_relative_residual;
}

/// True when a known load discontinuity lies at the start t_n of the step [t_n, t_n + h]: the
/// loads carried over from the previous step are then left limits and must be re-evaluated.
/// The match tolerance 1e-9·max(h, |t_n|) is that of core::is_multiple_of, which the driver
/// used to put the discontinuity on the grid.
bool starts_on_discontinuity(std::span<const double> discontinuities, double t_n, double h);

/// Every position, attitude and velocity of every body is finite.
bool all_finite(const core::State& state);

/// Renormalizes the product of two unit quaternions. Its squared norm is 1 + δ with δ a few ε,
/// so one Newton step for 1/√x at x = 1, θ ← θ (3 − |θ|²)/2, leaves an error (3/8)δ² — below
/// round-off — without a square root or a division on the step's critical path.
inline void renormalize_unit_product(rotation::EulerParameters& theta) {
  theta *= 0.5 * (3.0 - theta.squaredNorm());
}

/// The explicit configuration update of C2 and NMB (Newmark β = 0) for every body:
///   x_{n+1} = x_n + h v_n + ½ h² a_n            (free bodies; a pivot body stays put)
///   Θ = h W_n + ½ h² A_n,  R_{n+1} = R_n exp(Θ̃)   (θ_{n+1} = θ_n ⊗ exp(Θ), renormalized)
/// and the predicted velocities v_n + h a_n, W_n + h A_n, seen only by velocity-dependent
/// loads at the step's one evaluation.
void predict_configuration(const core::Model& model, const core::State& state,
                           const core::Accelerations& acc, double h, core::State& next);

/// The central-difference velocity update of a body's translation, shared by all schemes:
///   a_{n+1} = f_{n+1}/m,  v_{n+1} = v_n + ½ h (a_n + a_{n+1})   (a pivot body: a = 0).
void update_translation(const core::Body& body, const core::Wrench& wrench,
                        const core::BodyState& state, const core::BodyAcceleration& acc, double h,
                        core::BodyState& next, core::BodyAcceleration& acc_next);

/// The hybrid scheme's modal part and prescribed bodies, before the step's force evaluation:
///   q_{n+1} = q_n + h q̇_n + ½ h² q̈_n,  q̇ ← q̇_n + h q̈_n   (central differences; the predicted
///   rate is seen only by the modal damping, an O(h²) error like the explicit predictor of
///   velocity-dependent loads)
/// and the rigid part of every prescribed body from its law at t_{n+1}.
void predict_modes(const core::Model& model, const core::State& state,
                   const core::Accelerations& acc, double h, double t_np1, core::State& next);
/// After the rigid update to t_{n+1} (W_{n+1}, a_{n+1} known; end_loads, the loads at the new
/// configuration `next` in ws, needed where the model has flexible bodies): the modal
/// accelerations from the LTE modal equation with the rigid accelerations of the same step,
/// a_{n+1} and α̅_{n+1} = J⁻¹ (T_{n+1} − W_{n+1} × J W_{n+1}) (the Euler equation at t_{n+1},
/// second-order accurate for every scheme; NMB's A_{n+1} is this value), then
///   q̇_{n+1} = q̇_n + ½ h (q̈_n + q̈_{n+1}).
/// Prescribed bodies take the law's α̅ at t_np1 (stored in acc_next).
void update_modes(const core::Model& model, const core::Loads* end_loads, double t_np1,
                  core::Workspace& ws, const core::State& state, const core::Accelerations& acc,
                  double h, core::State& next, core::Accelerations& acc_next);
/// What the hybrid schemes (C1, C2, NMB) can step, checked when one is made: throws
/// std::invalid_argument naming a joint when the model has ideal joints (their rotation updates
/// have no multipliers: docs/joints.md), and when it has a flexible body under the coupled
/// formulation (they integrate the LTE model, the paper's final algorithm).
void require_hybrid_scheme_model(const core::Model& model, const char* scheme);
/// "<scheme> Newton did not converge at t = …, h = …: residual … after … iterations (body …)".
std::string newton_failure(const char* scheme, double t_n, double h, double relative_residual,
                           int iterations, int body);
/// "<scheme>: non-finite state at t = … (step from t_n with h = …)".
std::string non_finite_failure(const char* scheme, double t_n, double h);

/// Largest |component| of a 3-vector (the norm the Newton tests use).
inline double max_abs(const Eigen::Vector3d& v) { return v.cwiseAbs().maxCoeff(); }

}  // namespace flexref::lie::detail
