#pragma once
/// \file step_advice.hpp
/// What `run` says about its step: a warning when h·|W| exceeds the scheme's measured
/// rotational stability limit (lie/rotational_stability.hpp), and the step to use when a run
/// fails or breaks the scene's invariants (core/invariants.hpp).
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::app {

/// The warning for a step whose h·|W| (|W| the largest spin of a body the scheme integrates, in
/// `state` at time t) exceeds the scheme's measured limit; empty when it does not, or when the
/// scheme has no measured limit.
std::string rotational_step_warning(const core::Model& model, const std::string& scheme, double dt,
                                    const core::State& state, double t);

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
