#include "reference/sundials_segment_driver.hpp"

#include <algorithm>
#include <cstddef>
#include <ctime>
#include <limits>

#include "core/error.hpp"

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
  const bool track_work = model.dissipates();
  double work = 0.0;  // W_d carried across restarts
  for (std::size_t k = 0; k < plan.initial_outputs; ++k) {
    run.trajectory.states.push_back(state);
    if (track_work) run.trajectory.dissipated_work.push_back(0.0);
  }
  if (plan.segments.empty()) return run;

  const std::unique_ptr<SegmentSolver> solver = make_solver();
  double t_reached = 0.0;
  std::clock_t cpu = 0;
  try {
    for (const Segment& segment : plan.segments) {
      const std::clock_t start = std::clock();
      try {
        solver->start_segment(segment, state, work);
      } catch (const StartError& e) {
        throw core::SolverError(solver_name, segment.start, run.stats.steps, e.what());
      }
      t_reached = segment.start;
      cpu += std::clock() - start;

      // `next`: the time the driver asks for after tout (the next output or the segment end),
      // so that a solver can tell whether tout is the only output inside its current step.
      const auto advance_to = [&](double tout, double next) {
        const std::clock_t solve_start = std::clock();
        double t_returned = t_reached;
        while (t_returned < tout) {
          const SegmentSolver::Advance reached = solver->advance(tout, next);
          if (reached.root) {
            // A contact onset or release: restart there (new order-1 step sequence).
            t_returned = reached.t;
            run.event_times.push_back(t_returned);
            ++run.stats.events;
            solver->add_counters(run.stats);
            solver->restart_at_root(t_returned, segment);
          } else {
            t_returned = tout;
          }
        }
        cpu += std::clock() - solve_start;
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
        run.trajectory.states.push_back(state);
        if (track_work) run.trajectory.dissipated_work.push_back(solver->dissipated_work());
      }
      if (t_reached < segment.end) advance_to(segment.end, kNever);
      // The state is continuous across a load switch; unpacking normalizes θ, so the restart
      // also projects the Euler parameters back onto the unit sphere.
      solver->unpack(t_reached, state);
      work = solver->dissipated_work();
      solver->add_counters(run.stats);
    }
  } catch (const SundialsError& e) {
    throw core::SolverError(solver_name, solver->current_time(t_reached),
                            run.stats.steps + solver->current_steps(),
                            solver->failure_message(e.what()));
  }
  run.stats.cpu_seconds = static_cast<double>(cpu) / CLOCKS_PER_SEC;
  return run;
}

}  // namespace flexref::reference::sundials
