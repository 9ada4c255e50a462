#pragma once
/// \file step_advice.hpp
/// What `run` says about its step: a warning when h·|W| exceeds the scheme's measured
/// rotational stability limit (lie/rotational_stability.hpp), and the step to use when a run
/// fails or breaks the scene's invariants (core/invariants.hpp).
#include <string>
#include <vector>

#include "core/force_element.hpp"
#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::app {

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

}  // namespace flexref::app
