#pragma once
/// \file reduced_cvode.hpp
/// CVODE on the reduced (joint-coordinate) form of a jointed rigid model (docs/
/// reduced_coordinates.md, "The reference" and "In the product"): y = (q, u, works) with
///   q̇ = u (angles, slides),  θ̇ = ½ θ̂ ⊗ (0, ω̄) (Euler parameters),
///   u̇ = constraint::ReducedModel::accelerations with Baumgarte's rate on the loop closures,
///   the works' rates Model::integral_rates at the bodies' states (the drives' power from the
///   closures' reactions),
/// Adams–Moulton with fixed-point iteration and Anderson acceleration of depth 1, switching to
/// Newton on CVODE's dense difference quotients where the iteration stalls (a mechanism nearing a
/// dead point), as the maximal CVODE reference on ideal joints (reference/cvode_solver.cpp). The
/// error weights per unit step of reference/error_weights.hpp on the coordinates that turn
/// (angles, Euler parameters) and their rates, SUNDIALS' rtol |y_i| + atol on the others, the
/// works' of reference/integral_weights.hpp. Baumgarte's rate by the maximal rule
/// (constraint_stabilization_rate) on the spectrum of the reduced ODE's own Jacobian, which also
/// chooses the method (choose_cvode_method: the form applies where it is Adams).
///
/// Driven by the segment loop every SUNDIALS reference shares (sundials_segment_driver.hpp):
/// stops at load switches, outputs from CVODE's interpolation, the bodies' states by forward
/// kinematics. The closures' rows in force move with a constraint::ClosureTracker at the steps
/// CVODE accepts (their re-choice and the orientation test for a singular configuration passed).
#include <vector>

#include "core/model.hpp"
#include "reference/reference_solver.hpp"

namespace flexref::reference {

/// The joint-coordinate reference from the model's consistent initial state at t = 0 to the
/// output times. Throws std::invalid_argument where the form does not apply (the reason named:
/// no ideal joints, flexible or prescribed bodies, contact, other constraints, a method other
/// than Adams asked for or chosen by the spectrum) or for bad times and tolerances;
/// core::SolverError naming the time, step and why where CVODE fails (a singular configuration
/// among them).
ReferenceRun solve_reduced_cvode(const core::Model& model, const std::vector<double>& output_times,
                                 const SolverOptions& options);

/// CVODE's reference in the coordinates options.coordinates asks for: kJoint
/// solve_reduced_cvode; kMaximal solve_cvode; kAuto the joint coordinates where they apply,
/// else the maximal ones. ReferenceRun::coordinates and its reason say which and why.
ReferenceRun solve_cvode_in_coordinates(const core::Model& model,
                                        const std::vector<double>& output_times,
                                        const SolverOptions& options);

}  // namespace flexref::reference
