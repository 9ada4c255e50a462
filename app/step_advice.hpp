#pragma once
/// \file step_advice.hpp
/// What `run` says about its step: a warning when h·|W| exceeds the scheme's measured
/// rotational stability limit (lie/rotational_stability.hpp), and the step to use when a run
/// fails or breaks the scene's invariants (core/invariants.hpp).
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/force_element.hpp"
#include "core/invariants.hpp"
#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::app {

/// A number as the messages print it (3 significant digits): the step the user types is the
/// one the advice checked.
std::string short_text(double x);

/// The warning for a step whose h·|W| (|W| the largest spin of a body the scheme integrates, in
/// `state` at time t) exceeds the scheme's measured limit; empty when it does not, or when the
/// scheme has no measured limit.
std::string rotational_step_warning(const core::Model& model, const std::string& scheme, double dt,
                                    const core::State& state, double t);

/// The warning for a step above a stiff mode's explicit limit 2/omega (core/step_limit.hpp: a
/// flexible body's highest mode, a contact, bushing or spring), in words true for the scheme: C1,
/// C2 and NMB integrate translation and modes by explicit central differences, unstable there;
/// genalpha is implicit, stable but the mode not resolved (h omega > 2: a period error beyond
/// 27 %, app/genalpha_step.hpp); of another registered method flexref knows neither, and says
/// both. Empty when dt is within the limit.
std::string stiff_mode_warning(const std::string& scheme, double dt, const core::PenaltyMode& mode);

/// The largest step of the form {1, 2, 5}·10^k, as printed with three digits, that is at most
/// `bound`, at least `smallest` and on the output grid (`times`) and the load discontinuities;
/// 0 when there is none.
double round_step(const core::Model& model, double bound, const std::vector<double>& times,
                  double smallest);

/// The step to suggest: the largest step of the form {1, 2, 5}·10^k that is on the output grid
/// (`times`) and the load discontinuities, at most half the model's explicit step limit and a
/// tenth of the scheme's rotational limit over `spin` (rad/s; 0: none), and at most dt/2 (a
/// failed run at dt needs a smaller step even below both limits). 0 when none down to 1e-6·dt
/// exists.
double suggested_step(const core::Model& model, const std::string& scheme, double dt,
                      const std::vector<double>& times, double spin);

/// "; nothing was written: use --dt 2e-05 (half the explicit step limit 9.46e-05 s of contact[1]
/// friction)", naming what limits the suggested step; "" when there is none.
std::string step_advice(const core::Model& model, const std::string& scheme, double dt,
                        const std::vector<double>& times, double spin);

/// What one run of a scheme did: passed (its trajectory and invariants), or where and why it
/// failed — a failed step, a broken invariant, or its joints left.
struct RunAttempt {
  bool passed = false;
  core::Trajectory trajectory;
  core::InvariantCheck invariants;
  std::string solver;       ///< who failed
  double time = 0.0;        ///< when, s
  long step = -1;           ///< at which step (−1: not known)
  std::string why;          ///< why, without advice
  double spin_until = 0.0;  ///< the spin before this time sets the step to suggest
  /// A broken invariant: its quantity and relative change (of its scale); NaN otherwise.
  std::string quantity;
  double change = std::numeric_limits<double>::quiet_NaN();
};

/// A broken invariant whose change at the smaller step is above this fraction of the change at
/// the failed one did not shrink with the step: a consistent scheme's error falls at least by
/// the step ratio (order 1; by its square at order 2), and the suggested steps are at most half
/// the failed one, so a change the step causes falls to ≤ 0.5 of itself; 0.8 leaves room for the
/// breach being seen at another output time.
inline constexpr double kUnshrunkChange = 0.8;

/// The advice for a run that failed at dt, never a step that cannot help: the suggested step
/// (suggested_step) is run once (`retry`); "; nothing was written: use --dt H (…; checked: a run
/// at that step passes)" when it passes; "; nothing was written; a smaller step does not help:
/// …" when it fails alike (an invariant whose change does not shrink, kUnshrunkChange; a step
/// that fails at the same time: a dead point or a discontinuity the scheme cannot cross); else
/// one more suggested step, then "; nothing was written; no step down to H passed".
std::string verified_step_advice(const core::Model& model, const std::string& scheme, double dt,
                                 const std::vector<double>& times, double spin,
                                 const RunAttempt& failed,
                                 const std::function<RunAttempt(double)>& retry);

}  // namespace flexref::app
