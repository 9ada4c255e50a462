#pragma once
/// \file method_choice.hpp
/// CVODE's method for a model (docs/references.md, "CVODE: Adams or BDF"). Adams–Moulton of
/// orders up to 12 needs fewer steps than BDF (orders ≤ 5) wherever accuracy, not stability,
/// sets the step — measured on every bundled scene without contact, flexible ones and a
/// double pendulum on stiff, lightly damped joints (2.6e3 rad/s) included. Its stability
/// region is bounded on the negative real axis, so BDF (with the projection of θ) is chosen
/// where a mode decays much faster than anything the solution must resolve:
///  - a contact (switching functions): penalty contacts are stiff, dissipative and non-smooth
///    at their force clamp, and engage only later in the run where the initial state shows
///    nothing (measured: BDF 1e4× more accurate per rtol on pendulum_on_sliding_support,
///    cheaper on sliding_block and top_on_plane);
///  - a heavily damped fast mode in the spectrum of the ODE Jacobian J at the initial state
///    (difference quotients, the loads of the first segment): the fastest decay rate
///    σ = max(−Re λ) exceeds kStiffnessRatio times every rate the solution must resolve — the
///    magnitudes |λ| of the modes damped less than critically ratio 1/√2 (|Re λ| ≤ |Im λ|), the
///    growth rates Re λ > 0 of unstable modes (a linearization away from equilibrium has real
///    pairs ±σ, whose decaying half is no stiffer than the growing one the step must follow)
///    and the bodies' angular speeds.
/// BDF capped at order 2 (kBdf2, A-stable) is chosen before either where a lightly damped mode
/// (|Re λ| ≤ |Im λ|, undamped modes on the imaginary axis) oscillates much faster than every
/// rate the solution is asked to show: more than kStiffnessRatio × the accuracy rate
/// ω_acc = max(π/Δt_out, max |ω̄(0)|), the Nyquist rate of the output grid (Δt_out the mean
/// output spacing) and the bodies' angular speeds. Such a mode carries no resolvable content at
/// the outputs; an accuracy-set step then has h·ω ≫ 1 on it, where Adams is unstable and BDF3–5
/// are unstable on a band of the imaginary axis (stability angles 86°, 73°, 52°): measured on
/// flexible_spinner_64 (ω_max = 1.8e4 rad/s, ω_acc = 314 rad/s), BDF ≤ 5 grows the upper modes
/// from rounding to 1e-5 within 0.05 s and then resolves them (337 677 steps for 10 s), BDF ≤ 2
/// damps them and follows the motion (docs/references.md, "Stiff oscillatory scenes"). If such
/// a mode is excited, the error test still resolves it and the honest error estimate (100×
/// tighter checks, one by another solver) shows any damping BDF2 puts on it. Not for a model
/// with contacts, which keeps BDF ≤ 5: contact modes are damped by the contact law and engaged
/// intermittently (pendulum_on_sliding_support has a 3.2e3 rad/s mode with ζ ≈ 0.2 at its
/// initial state; measured at rtol 1e-8: BDF ≤ 5 31 789 steps, 0.31 s; ESDIRK 2.5 s).
#include <complex>
#include <span>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "reference/reference_solver.hpp"

namespace flexref::reference {

/// σ beyond this multiple of the resolved rates makes the model stiff.
inline constexpr double kStiffnessRatio = 10.0;

/// The spectrum summary the choice is made from (rates in 1/s).
struct StiffnessSummary {
  int switching_functions = 0;
  double accuracy_rate = 0.0;        ///< ω_acc; +∞ when no output spacing was given
  double fastest_oscillation = 0.0;  ///< max |λ| over modes with |Re λ| ≤ |Im λ|
  double fastest_rate = 0.0;         ///< max |λ| of J
  double fastest_decay = 0.0;        ///< σ = max(−Re λ), 0 when no mode decays
  double resolved_rate = 0.0;  ///< max |λ| over modes with |Re λ| ≤ |Im λ|, and max |ω̄(0)|
  bool stiff() const;
  /// A lightly damped mode faster than kStiffnessRatio × ω_acc, and no contact.
  bool stiff_oscillatory() const;
};

/// output_spacing: the mean spacing of the output times (s); 0 leaves ω_acc = +∞ (no
/// oscillatory stiffness).
StiffnessSummary summarize_stiffness(const core::Model& model, double output_spacing = 0.0);
/// The same reading of the eigenvalues of another ODE form of the model at its initial state
/// (the joint-coordinate form, reference/reduced_cvode.hpp): real parts within `noise` (the
/// difference quotients' noise, ~1e-6 of the Jacobian's largest entry) count as zero; the
/// switching functions and the bodies' angular speeds are the model's.
StiffnessSummary summarize_spectrum(const core::Model& model,
                                    std::span<const std::complex<double>> eigenvalues, double noise,
                                    double output_spacing);

/// (last − first)/(count − 1) of the output times; the last time itself (from t = 0) for one.
double mean_output_spacing(const std::vector<double>& output_times);

struct CvodeMethodChoice {
  CvodeMethod method = CvodeMethod::kAdams;
  std::string reason;  ///< for the metadata: the element or the rates behind the choice
};

/// kBdf for contact, else kBdf2 if stiff_oscillatory(), else kBdf if stiff(), else kAdams.
CvodeMethodChoice choose_cvode_method(const core::Model& model, double output_spacing = 0.0);
/// The same from the model's summary (summarize_stiffness), for a caller that reads it twice
/// (each summary is a difference-quotient Jacobian and its spectrum).
CvodeMethodChoice choose_cvode_method(const StiffnessSummary& summary);

/// IDA's order cap from the same summary: kBdf2 if stiff_oscillatory(), else kBdf.
CvodeMethodChoice choose_ida_method(const core::Model& model, double output_spacing);

struct ArkodeMethodChoice {
  ArkodeMethod method = ArkodeMethod::kErk;
  std::string reason;
};

/// ARKODE's method: the implicit ESDIRK (L-stable) if stiff_oscillatory(), else the explicit
/// Fehlberg 13-7-8.
ArkodeMethodChoice choose_arkode_method(const core::Model& model, double output_spacing);
ArkodeMethodChoice choose_arkode_method(const StiffnessSummary& summary);

/// The default reference solver (`flexref reference` without --solver; "auto" in the studies for
/// a model without an exact solution): "arkode" (which then runs its ESDIRK) for a stiff
/// oscillatory model — measured on flexible_spinner_64, ESDIRK5(4)7L[2]SA reaches 3.4e-7 in
/// 0.38 s where CVODE's BDF2 needs 2.3 s for 6.4e-6 (docs/references.md) — else "cvode". Odeint
/// reaches CVODE's accuracy at 1/3.6–1/4.5 of its CPU time on the smooth exact scenes (heavy_top,
/// free_spin, pendulum) but not on book_toss at the studies' rtol 1e-12 (1.9e-8 against CVODE's
/// 6.5e-9 rad: its floor), so it is not the default (docs/references.md, "The default solver").
struct ReferenceSolverChoice {
  std::string solver;
  std::string reason;
};
ReferenceSolverChoice choose_reference_solver(const core::Model& model, double output_spacing);

/// Whether CVODE and IDA weigh each body's rotation per unit step (reference/error_weights.hpp):
/// a model without contact whose spectrum is neither stiff nor stiff oscillatory — where the
/// rotation's accuracy, not stiffness or events, sets the steps (Adams' domain in
/// choose_cvode_method); for IDA on ideal joints with a higher floor
/// (ErrorWeights::kIndex2Roundoff).
bool rotation_weights_per_step(const StiffnessSummary& summary);

/// The Jacobian and linear solver of the implicit solvers' Newton systems.
enum class NewtonJacobian {
  kDifferenceQuotients,  ///< the solver's own difference quotients, dense LU
  kStructured,           ///< StructuredJacobian + the structured Newton solve (newton_matrix.hpp)
  kUser,                 ///< SolverOptions::jacobian, dense LU
  kColoured,             ///< IDA on ideal joints: coloured difference quotients, KLU
                         ///< (dae_coloured_jacobian.hpp)
};

/// Baumgarte's rate α for a model with ideal joints integrated without projection (CVODE's
/// Adams, ARKODE, Odeint; docs/joints.md, "References"): the fastest rate the solution must
/// resolve at the initial state (StiffnessSummary::resolved_rate: oscillations, growth rates and
/// the bodies' angular speeds), or π/Δt_out when none is known. The drift of Φ and J v + Φ_t,
/// fed by the local errors, then decays at α instead of growing linearly and quadratically,
/// and h·α stays within the step's accuracy range, so the term adds no stiffness. 0 without
/// joints.
double constraint_stabilization_rate(const core::Model& model, double output_spacing);
/// The same from the model's summary at that output spacing.
double constraint_stabilization_rate(const core::Model& model, const StiffnessSummary& summary,
                                     double output_spacing);

/// kDifferenceQuotients for a model with ideal joints (the user's and the structured Jacobians
/// are the unconstrained equations'); kUser when the options give a Jacobian; kStructured for a
/// model with flexible bodies (its
/// modal blocks make difference quotients cost 1 + dim y evaluations of O(n²) and the dense LU
/// O((13 + 2n)³); docs/performance.md); otherwise kDifferenceQuotients (rigid models keep
/// SUNDIALS' own, the figures of docs/references.md).
NewtonJacobian choose_newton_jacobian(const core::Model& model, const SolverOptions& options);
/// IDA's: choose_newton_jacobian's, but kColoured for a model with ideal joints unless
/// options.newton_matrix asks for the dense one (kDense). No jointed model was measured faster
/// with the dense matrix, from one body on (docs/performance.md, "Constrained systems at
/// scale"): the coloured quotients cost fewer residuals from the smallest mechanism up.
NewtonJacobian choose_ida_newton_jacobian(const core::Model& model, const SolverOptions& options);
const char* to_string(NewtonJacobian jacobian);

}  // namespace flexref::reference
