#include "reference/sundials_segment_driver.hpp"

#include <algorithm>
#include <cstddef>
#include <ctime>
#include <limits>
#include <optional>
#include <vector>

#include "core/error.hpp"
#include "core/impact_counter.hpp"
#include "reference/solve_progress.hpp"

namespace flexref::reference::sundials {

namespace {
constexpr double kNever = std::numeric_limits<double>::infinity();
}  // namespace

ReferenceRun integrate_segments(const core::Model& model, const std::vector<double>& output_times,
                                const SolverOptions& options, const std::string& solver_name,
                                const SegmentSolverFactory& make_solver) {
  validate_tolerances(options.rtol, options.absolute_tolerance(), options.max_steps);
  const SegmentPlan plan = plan_segments(model.discontinuities(), output_times);

  ReferenceRun run;
  run.solver = solver_name;
  run.options = options;
  run.trajectory.times = output_times;
  run.trajectory.states.reserve(output_times.size());
  core::State state = model.initial_state();
  const bool track_work = model.tracks_work();
  // W_d and the extra integrals (applied work, wear work), carried across restarts.
  std::vector<double> integrals(
      track_work ? static_cast<std::size_t>(1 + model.extra_integral_count()) : 0, 0.0);
  // The impact counter and its workspace only where there are contacts to count (a workspace
  // sizes the joints' constrained solve, which nothing here uses otherwise).
  const bool count_impacts = model.wear_channel_count() > 0;
  core::ImpactCounter impacts(model);
  std::optional<core::Workspace> impact_ws;
  if (count_impacts) {
    impact_ws.emplace(model.make_workspace());
    impacts.start(core::LoadContext{0.0, 0.0}, state, *impact_ws);
  }
  const auto record = [&](double t) {
    run.trajectory.states.push_back(state);
    if (options.progress != nullptr) options.progress->reached(t);
    if (track_work) {
      run.trajectory.dissipated_work.push_back(integrals[0]);
      run.trajectory.extra_work.insert(run.trajectory.extra_work.end(), integrals.begin() + 1,
                                       integrals.end());
    }
    if (count_impacts) {
      impacts.update(core::LoadContext{t, t}, state, *impact_ws);
      run.trajectory.impacts.insert(run.trajectory.impacts.end(), impacts.counts().begin(),
                                    impacts.counts().end());
    }
  };
  for (std::size_t k = 0; k < plan.initial_outputs; ++k) record(output_times[k]);
  if (plan.segments.empty()) return run;

  const std::unique_ptr<SegmentSolver> solver = make_solver();
  double t_reached = 0.0;
  // The process's CPU clock is read at each segment's start and end: its outputs' states are
  // counted with the integration, as Odeint's (odeint_solver.cpp). Read around each output's
  // advance instead, it cost about as much as what it left out: each read is a system call
  // (~0.6 µs of CPU on the project's machine, two per output), an output's state a few µs.
  std::clock_t cpu = 0;
  try {
    for (const Segment& segment : plan.segments) {
      const std::clock_t start = std::clock();
      try {
        solver->start_segment(segment, state, integrals);
      } catch (const StartError& e) {
        throw core::SolverError(solver_name, segment.start, run.stats.steps, e.what());
      }
      t_reached = segment.start;

      // `next`: the time the driver asks for after tout (the next output or the segment end),
      // so that a solver can tell whether tout is the only output inside its current step.
      const auto advance_to = [&](double tout, double next) {
        double t_returned = t_reached;
        while (t_returned < tout) {
          const SegmentSolver::Advance reached = solver->advance(tout, next);
          if (reached.root) {
            // A contact onset or release: restart there (new order-1 step sequence).
            t_returned = reached.t;
            run.event_times.push_back(t_returned);
            ++run.stats.events;
            if (count_impacts) {
              // The root finder returns the state just past the sign change: an onset is seen
              // here, however short the contact.
              solver->unpack(t_returned, state);
              impacts.update_at_root(core::LoadContext{t_returned, segment.t_segment}, state,
                                     *impact_ws);
            }
            solver->add_counters(run.stats);
            solver->restart_at_root(t_returned, segment);
          } else {
            t_returned = tout;
          }
        }
        t_reached = tout;
      };
      for (std::size_t k = segment.first_output; k < segment.end_output; ++k) {
        // Outputs within boundary_slack of the segment end are taken at the end.
        const double tout = std::min(output_times[k], segment.end);
        const double next = k + 1 < segment.end_output
                                ? std::min(output_times[k + 1], segment.end)
                                : (tout < segment.end ? segment.end : kNever);
        if (tout > t_reached) advance_to(tout, next);
        solver->unpack(tout, state);
        solver->accept_output(tout, state);
        if (track_work) solver->integrals(integrals);
        record(tout);
      }
      if (t_reached < segment.end) advance_to(segment.end, kNever);
      // The state is continuous across a load switch; unpacking normalizes θ, so the restart
      // also projects the Euler parameters back onto the unit sphere.
      solver->unpack(t_reached, state);
      if (track_work) solver->integrals(integrals);
      cpu += std::clock() - start;
      solver->add_counters(run.stats);
    }
  } catch (const SundialsError& e) {
    throw core::SolverError(solver_name, solver->current_time(t_reached),
                            run.stats.steps + solver->current_steps(),
                            solver->failure_message(e.what()));
  } catch (const core::SingularConfigurationError& e) {
    // Found where the solver's tracker moved to an output, a segment's start or a restart.
    throw core::SolverError(solver_name, e.time(), run.stats.steps + solver->current_steps(),
                            e.what());
  }
  run.stats.cpu_seconds = static_cast<double>(cpu) / CLOCKS_PER_SEC;
  return run;
}

}  // namespace flexref::reference::sundials
