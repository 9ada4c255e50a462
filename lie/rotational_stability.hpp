#pragma once
/// \file rotational_stability.hpp
/// The measured rotational stability limits of the built-in schemes: the largest h·|W| (step
/// times the body's angular speed) at which each stays stable on a torque-free rigid body. The
/// one place these numbers live; `run` warns above them, the README and docs quote them, and
/// tests/studies/stability_limits_test.cpp measures them again with the `stability` study.
///
/// How they were measured (`flexref stability --parameter spin`, studies/stability.hpp): free
/// body J = diag(3, 4, 5) kg·m² (free_spin's), W0 along (0.2, 0.3, 2.0), spin rates 0.1 … 1000
/// rad/s (h_max·|W| is the same at every rate: a fixed number of steps makes the test invariant
/// under W → sW, h → h/s); a run of 1000 steps is unstable when a state turns non-finite, a
/// Newton solve fails, or the energy or the angular momentum leaves ±50 % of its initial value;
/// bisection to 1e-3 relative, the first limit above h|W| = 1e-3. Rounded down to three digits.
///
/// The limit is a property of the scheme and the body's shape: other inertia ratios and spin
/// directions move it (docs/schemes.md: C2 runs away at h|W| = 0.5 with W0 = (3, 10, 2)), so a
/// step below it is no guarantee; the run's invariant monitor (core/invariants.hpp) judges the
/// run itself.
#include <string_view>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::lie {

/// The measured limit h·|W| of a built-in scheme ("c1" 8.96, "c2" 0.582, "nmb" 3.81), or 0
/// for a scheme that was not measured (a user's method).
double rotational_stability_limit(std::string_view scheme);

/// The largest angular speed |W| (rad/s) of a body whose rotation a scheme integrates (free or
/// pivot bodies; a prescribed frame follows its law) in the state, and that body's index (−1
/// when there is none).
struct SpinRate {
  double w = 0.0;  ///< rad/s
  int body = -1;
};
SpinRate largest_spin(const core::Model& model, const core::State& state);

}  // namespace flexref::lie
