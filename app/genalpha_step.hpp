#pragma once
/// \file genalpha_step.hpp
/// The step `flexref check` advises for genalpha (docs/schemes.md, "Step advice for genalpha").
///
/// genalpha is implicit: on an undamped linear mode its one-step map has spectral radius ≤ 1 at
/// every h ω, so no mode bounds its step for stability, unlike the explicit step limit 2/ω of
/// the hybrid schemes' central differences (core/step_limit.hpp). What bounds it is accuracy: a
/// motion at the rate ω is followed with the method's relative period error on the undamped
/// oscillator x'' = −ω² x,
///
///   ΔT/T = c(ρ∞) (h ω)² + O((h ω)⁴),   c(ρ∞) = 1/12 + (3/8) ((1 − ρ∞)/(1 + ρ∞))²,
///
/// the trapezoidal rule's 1/12 at ρ∞ = 1, plus the price of the numerical damping
/// (α_f − α_m = (1 − ρ∞)/(1 + ρ∞), lie/genalpha_parameters.hpp); 0.0844 at the default
/// ρ∞ = 0.9 (read off the eigenvalues of the scheme's one-step map;
/// tests/app/genalpha_step_test.cpp checks it on the stepper itself). The advice keeps it at most
/// kGenalphaPeriodError (1 %) on the fastest rate the scene shows at t0: h ω ≤ √(0.01 / c(ρ∞)),
/// 0.344 at ρ∞ = 0.9, about 18 steps per period.
///
/// The rates (rad/s or 1/s), each as `check` names it:
///  - every penalty mode but the friction dampers: a spring's, a bushing's, a contact's
///    ω = √(k/m_eff) (core::penalty_modes; an impact lasts π/ω). A friction regularization is a
///    decay (rate c_t/m_eff), which an implicit method damps stably without resolving it;
///  - the bodies' angular speeds |W| at t0, a prescribed body's rate and every revolute drive's
///    rate (a spin-up's final rate), and 2π/T_s of every spin-up law (its acceleration is
///    (Ω/T_s)(1 − cos(2πt/T_s))). A prismatic drive's rate is a speed (m/s), not a rate: it
///    enters only through the motion it causes, which the next item sees;
///  - the linearized motion at t0: the largest |λ| of the ODE Jacobian's lightly damped modes and
///    its growth rates (reference::summarize_stiffness, the reference solvers' own analysis: a
///    compound pendulum's √(m g d/I_O) on its joint, Andrews' squeezer's growth rate 471/s);
///  - each flexible body's highest natural frequency at most kStiffnessRatio × the accuracy rate
///    ω_acc = max(π/Δt_out, |W|) — the cut below which the references resolve a mode
///    (reference/method_choice.hpp): a faster lightly damped mode carries nothing the outputs
///    show, and genalpha damps it (ρ∞ < 1) instead of resolving it. A scene with such a mode
///    (stiff oscillatory) leaves the Jacobian's rate out too, since its largest |λ| is that mode.
/// The advice is a property of the initial state: a mechanism that speeds up later (Andrews'
/// squeezer turns at ~1e3 rad/s by t = 0.03 s from rest) needs a smaller step then, which
/// `converge` shows.
#include <string>
#include <vector>

#include "core/model.hpp"

namespace flexref::app {

/// The relative period error genalpha may have on the fastest rate of the scene.
inline constexpr double kGenalphaPeriodError = 0.01;

/// c(ρ∞) of the period error ΔT/T = c (h ω)² above.
double genalpha_period_error_coefficient(double rho_inf);

/// The fastest rate genalpha must resolve at t0 and the step it advises.
struct GenalphaStepAdvice {
  double rate = 0.0;   ///< ω, rad/s; 0 when the scene shows no rate at t0
  std::string what;    ///< what sets it, e.g. "spring 'S1' (omega = sqrt(k/m_eff))"
  double bound = 0.0;  ///< s: √(kGenalphaPeriodError / c(ρ∞)) / ω (+∞ without a rate)
  double step = 0.0;   ///< s: app::round_step of the bound on the output grid; 0 when none
};

/// The advice at the spectral radius rho_inf for the output times `times` (the scene's grid).
GenalphaStepAdvice genalpha_step_advice(const core::Model& model, const std::vector<double>& times,
                                        double rho_inf);

}  // namespace flexref::app
