/// \file odeint_solver.cpp
/// Boost.Odeint's controlled Runge–Kutta–Fehlberg 7(8) on the quasi-velocity ODE form
/// (reference/ode_form.hpp): the independent cross-check of the SUNDIALS drivers
/// (docs/design/schemes.md, "Reference integrators"; docs/references.md). It shares nothing with
/// them but the model and the ODE form: its own segment plan, stepping loop, dense output, event
/// location and failure handling.
///
/// - Error control: odeint's default checker, err_i / (atol + rtol (|x_i| + h |x'_i|)) ≤ 1 in
///   the max norm, step-size adjustment by odeint (make_controlled(atol, rtol, ...)).
/// - The step sequence is the tolerance's: steps end only where the error control, a known
///   load discontinuity (segment end, stepped onto exactly) or a located event puts them. Outputs
///   inside a step come from an order-8 continuous extension (reference/continuous_extension.hpp:
///   Hermite interpolation of degree 7 through the step's ends and two RKF7(8) steps of h/3 and
///   2h/3 from its start), or, for a step's only output, from one RKF7(8) step from the step's
///   start onto it; an output on a step end is that step's value.
/// - The Euler parameters are renormalized at every segment end (|θ| is a first integral of the
///   form in between, and the form is homogeneous in θ: its drift does not move the attitude).
/// - Switching functions (contact gaps, core::Model::switching_functions) are evaluated after
///   every accepted step; when one changes sign, the step is bisected on its length, re-taking
///   the RKF7(8) step from the accepted start each time (the step's own solution, as accurate as
///   the accepted step), down to a few ulp of t, and the step ends just past the zero. A trial
///   whose evaluations (not only its end) saw the other side counts as past the zero, so no
///   stage of the step onto the switch sees the new branch (a damped penalty law jumps at an
///   onset: locate_event). The event time is recorded; no step straddles a contact onset or
///   release, and the continuous extension of the step onto it uses the near side's derivative.
/// - SolverOptions::max_steps bounds the steps between two consecutive output times, as it
///   does for the SUNDIALS drivers (mxstep).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <ctime>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/impact_counter.hpp"
#include "reference/method_choice.hpp"
#include "reference/ode_form.hpp"
#include "reference/odeint_integrator.hpp"
#include "reference/reference_solver.hpp"
#include "reference/solve_progress.hpp"

namespace flexref::reference {
namespace {

using odeint_detail::Integrator;
using odeint_detail::time_slack;

void validate(const std::vector<double>& output_times, const SolverOptions& options) {
  const double rtol = options.rtol;
  const double atol = options.absolute_tolerance();
  if (!(rtol > 0.0) || !std::isfinite(rtol) || !(atol > 0.0) || !std::isfinite(atol)) {
    throw std::invalid_argument("tolerances must be positive and finite");
  }
  if (options.max_steps <= 0) throw std::invalid_argument("max_steps must be positive");
  if (output_times.empty()) throw std::invalid_argument("no output times");
  for (std::size_t k = 0; k < output_times.size(); ++k) {
    if (!std::isfinite(output_times[k]) || output_times[k] < 0.0) {
      throw std::invalid_argument("output times must be finite and non-negative");
    }
    if (k > 0 && !(output_times[k] > output_times[k - 1])) {
      throw std::invalid_argument("output times must be strictly increasing");
    }
  }
}

}  // namespace

ReferenceRun solve_odeint(const core::Model& model, const std::vector<double>& output_times,
                          const SolverOptions& options) {
  validate(output_times, options);
  // Odeint's steppers have no projection: the joints' drift is damped instead (Baumgarte).
  const reference::OdeForm form(
      model, constraint_stabilization_rate(model, mean_output_spacing(output_times)));

  ReferenceRun run;
  run.solver = "odeint";
  run.method = "rkf78";
  run.method_reason = "Boost.Odeint runge_kutta_fehlberg78, order-8 continuous extension";
  run.options = options;
  run.trajectory.times = output_times;
  run.trajectory.states.reserve(output_times.size());
  core::State state = model.initial_state();

  // Segment ends: the discontinuities inside (0, T), then T; the initial state is at t = 0.
  const double t_end = output_times.back();
  std::vector<double> ends;
  for (double d : model.discontinuities()) {
    const double previous = ends.empty() ? 0.0 : ends.back();
    if (d > previous + time_slack(d) && d < t_end - time_slack(t_end)) ends.push_back(d);
  }
  ends.push_back(t_end);

  std::size_t k = 0;
  const bool track_work = form.work_index() >= 0;
  std::vector<double> integrals(static_cast<std::size_t>(form.integral_count()), 0.0);
  const bool count_impacts = model.wear_channel_count() > 0;
  core::Workspace ws = model.make_workspace();
  core::ImpactCounter impacts(model);
  impacts.start(core::LoadContext{0.0, 0.0}, state, ws);
  core::State step_end = state;
  const auto record = [&]() {
    run.trajectory.states.push_back(state);
    if (options.progress != nullptr) options.progress->reached(output_times[k]);
    if (track_work) {
      run.trajectory.dissipated_work.push_back(integrals[0]);
      run.trajectory.extra_work.insert(run.trajectory.extra_work.end(), integrals.begin() + 1,
                                       integrals.end());
    }
    if (count_impacts) {
      run.trajectory.impacts.insert(run.trajectory.impacts.end(), impacts.counts().begin(),
                                    impacts.counts().end());
    }
  };
  for (; k < output_times.size() && output_times[k] <= time_slack(0.0); ++k) record();
  if (k == output_times.size()) return run;

  Integrator integrator(form, options, run.stats);
  integrator.record_events_in(&run.event_times);
  std::clock_t cpu = 0;
  try {
    double start = 0.0;
    for (double end : ends) {
      std::clock_t tic = std::clock();
      integrator.begin_segment(state, 0.5 * (start + end));
      cpu += std::clock() - tic;
      while (integrator.time() < end) {
        tic = std::clock();
        integrator.step(end);
        const double reached = integrator.time();
        // Outputs in the step just taken; those within a few ulp of the segment end at the end.
        const double last = reached == end ? end + time_slack(end) : reached;
        std::size_t inside = 0;  // outputs strictly inside the step
        for (std::size_t j = k; j < output_times.size() && output_times[j] <= last; ++j) {
          if (std::min(output_times[j], reached) < reached - time_slack(reached)) ++inside;
        }
        for (; k < output_times.size() && output_times[k] <= last; ++k) {
          const double t = std::min(output_times[k], reached);
          integrator.output(t, state, inside == 1);
          if (track_work) integrator.output_integrals(t, integrals);
          record();
        }
        if (count_impacts) {
          // Steps end just past a located event: an onset is seen at the step's end (after the
          // outputs inside the step, which precede it).
          integrator.unpack(step_end);
          impacts.update(core::LoadContext{reached, 0.5 * (start + end)}, step_end, ws);
        }
        cpu += std::clock() - tic;
      }
      tic = std::clock();
      integrator.normalize();
      cpu += std::clock() - tic;
      integrator.unpack(state);
      start = end;
    }
  } catch (const core::SolverError&) {
    throw;
  } catch (const std::exception& e) {
    throw core::SolverError("odeint", integrator.time(), run.stats.steps,
                            std::string("the right-hand side threw: ") + e.what());
  }
  run.stats.rhs_evaluations = integrator.rhs_evaluations();
  run.stats.cpu_seconds = static_cast<double>(cpu) / CLOCKS_PER_SEC;
  return run;
}

}  // namespace flexref::reference
