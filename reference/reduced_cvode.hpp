#pragma once
/// \file reduced_cvode.hpp
/// CVODE on the reduced (joint-coordinate) form of a jointed rigid model (docs/
/// reduced_coordinates.md, stage 2): y = (q, u) with
///   q̇ = u (angles, slides),  θ̇ = ½ θ̂ ⊗ (0, ω̄) (Euler parameters),
///   u̇ = constraint::ReducedModel::accelerations with Baumgarte's rate on the loop closures,
/// Adams–Moulton with fixed-point iteration and Anderson acceleration of depth 1, as the maximal
/// CVODE reference on ideal joints (reference/cvode_solver.cpp); the error weights per unit step
/// of reference/error_weights.hpp on the coordinates that turn (angles, Euler parameters) and
/// their rates, SUNDIALS' rtol |y_i| + atol on the others; Baumgarte's rate by the maximal rule
/// (constraint_stabilization_rate) read on the reduced ODE's own Jacobian. The outputs are the
/// bodies' states by forward kinematics at the output times, CVODE's interpolation of y in
/// between its steps (docs/reduced_coordinates.md, "The reference").
///
/// Not yet the maximal driver's equal: no segments (a model with known load switches is
/// refused), no event location (contacts are refused by ReducedModel), no work integrals, no
/// joint reactions in the outputs.
#include <string>
#include <vector>

#include "constraint/reduced_model.hpp"
#include "core/state.hpp"
#include "reference/reference_solver.hpp"

namespace flexref::reference {

struct ReducedRun {
  std::vector<double> times;
  std::vector<core::State> states;  ///< the bodies' states (forward kinematics) at `times`
  long steps = 0;
  long evaluations = 0;        ///< right-hand-side evaluations
  double stabilization = 0.0;  ///< Baumgarte's rate on the closures (1/s)
};

/// The reduced reference from the model's consistent initial state at t = 0 to the output
/// times (the first may be 0). Throws std::invalid_argument for bad times or tolerances and a
/// model with load switches, core::SolverError-like std::runtime_error naming CVODE's failure.
ReducedRun solve_reduced_cvode(const constraint::ReducedModel& reduced,
                               const std::vector<double>& output_times,
                               const SolverOptions& options);

}  // namespace flexref::reference
