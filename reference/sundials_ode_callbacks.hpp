#pragma once
/// \file sundials_ode_callbacks.hpp
/// The callbacks CVODE and ARKODE call on the ODE form (reference/ode_form.hpp): the
/// right-hand side, the switching functions (contact gaps) for root finding, the user Jacobian
/// (reference/ode_jacobian.hpp) and the projection of θ onto the unit sphere. CVRhsFn and
/// ARKRhsFn, CVRootFn and ARKRootFn have the same signatures. None allocates; none throws
/// through C: an exception is recorded in the CallbackRecord and the callback returns −1.
#include <nvector/nvector_serial.h>
#include <sundials/sundials_matrix.h>

#include <vector>

#include "reference/error_weights.hpp"
#include "reference/ode_form.hpp"
#include "reference/ode_jacobian.hpp"
#include "reference/step_clock.hpp"
#include "reference/structured_jacobian.hpp"
#include "reference/sundials_handle.hpp"

namespace flexref::reference::sundials {

/// user_data of the ODE callbacks.
struct OdeCallbackData : CallbackRecord {
  const OdeForm* form = nullptr;
  /// The joints' tracker of the integration (core/constraint_tracker.hpp), which
  /// scratch.tracker points to: moved by the driver at the states it accepts (accept_tracker),
  /// read by every callback.
  core::ConstraintTracker tracker;
  /// Set when an evaluation chose joint rows of its own (the tracker's were ill-conditioned at
  /// its state: core::JointMultipliers::rows_chosen), cleared where the tracker moves.
  bool rows_chosen = false;
  OdeForm::Scratch scratch;
  double t_segment = 0.0;  ///< selects the load branch of the current segment
  const OdeJacobian* jacobian = nullptr;
  /// For structured_ode_jacobian: the form's structured Jacobian and its per-run scratch.
  const StructuredJacobian* structured = nullptr;
  StructuredJacobian::Scratch structured_scratch;
  long evaluations = 0;  ///< calls of ode_rhs (ARKODE counts its main and auxiliary steps by it)
  /// When set, ode_rhs also evaluates the switching functions at each (t, y) (into
  /// watch_values, sized by the driver) and sets other_side when one is on another side than in
  /// *watch_start: a step's stages that saw a switch (ARKODE's event location).
  const std::vector<double>* watch_start = nullptr;
  std::vector<double> watch_values;
  bool other_side = false;
  /// project_constraints' copy of y (sized by the driver for models with ideal joints).
  std::vector<double> projected;
  /// CVODE only (its error-weight callback, cvode_solver.cpp): CVODE's memory to read the steps
  /// from.
  void* cvode = nullptr;
};

/// Sizes d.scratch for d.form and points it at d.tracker, which starts at the model's initial
/// rows. d must not move afterwards.
void bind_scratch(OdeCallbackData& d);

/// The tracker moved to the accepted state at t (a segment's start, a restart: from y; an
/// output: the state, as far as output_advance says; Model::advance_tracker). Throws
/// core::SingularConfigurationError.
void accept_tracker(OdeCallbackData& d, double t, const double* y);
void accept_output(OdeCallbackData& d, double t, const core::State& state);
/// At a step the solver accepted (t, y): where evaluations chose joint rows of their own since
/// the tracker last moved, it moves there and chooses the rows at the accepted state
/// (TrackerAdvance::kChooseRows), so that the next step's evaluations share them; otherwise
/// nothing (no factorization per step).
void accept_step(OdeCallbackData& d, double t, const double* y);

/// y' = f(t, y). Returns 1 (recoverable: the solver retries a smaller step) when f is not
/// finite, e.g. a trial step that reached a singular load.
int ode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data);

/// CVProjFn for models with ideal joints: the correction that puts the bodies' state on
/// Φ = 0, J v + Φ_t = 0 with unit θ (OdeForm::project); the error's θ parts projected as in
/// project_euler_parameters. Returns 1 (recoverable) when the projection fails.
int project_constraints(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps_proj,
                        N_Vector err, void* user_data);

/// The model's switching functions at (t, y).
int ode_switching(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data);

/// CVLsJacFn: J = ∂f/∂y from OdeCallbackData::jacobian.
int ode_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix jacobian, void* user_data,
                 N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);

/// CVLsJacFn and ARKLsJacFn: J = ∂f/∂y from OdeCallbackData::structured (every entry written;
/// allocates nothing). Returns 1 (recoverable) when J is not finite.
int structured_ode_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix jacobian,
                            void* user_data, N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);

/// CVProjFn: orthogonal projection onto |θ| = 1 per body, corr = θ/|θ| − θ (zero elsewhere);
/// the error estimate loses its component normal to the sphere, e_θ ← e_θ − (θ̂·e_θ) θ̂ (the
/// projection's Jacobian at the projected point; cf. cvParticle_dns.c in SUNDIALS).
int project_euler_parameters(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps_proj,
                             N_Vector err, void* user_data);

}  // namespace flexref::reference::sundials
