#include "lie/run_scheme.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/impact_counter.hpp"
#include "core/output_times.hpp"
#include "lie/scheme_support.hpp"

namespace flexref::lie {
namespace {

void require_on_grid(const char* what, double t, double t0, double dt) {
  if (core::is_multiple_of(t - t0, dt)) return;
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::digits10);  // 0.03 prints as 0.03
  out << what << " t = " << t << " is not on the step grid t0 + n·dt (t0 = " << t0
      << ", dt = " << dt << ")";
  throw std::invalid_argument(out.str());
}

long step_index(double t, double t0, double dt) { return std::lround((t - t0) / dt); }

/// The energy at an output time must be finite: a finite state can still carry an energy that
/// overflows (|W| ~ 1e160), and a CSV must never hold an inf.
void check_energy(const core::Model& model, const Stepper& stepper, double t, long n,
                  const core::State& state, core::Workspace& ws) {
  const double kinetic = model.kinetic_energy(state);
  const double potential = model.potential_energy(core::LoadContext{t, t}, state, ws);
  if (std::isfinite(kinetic) && std::isfinite(potential)) return;
  std::ostringstream why;
  why << "the energy is not finite (kinetic " << kinetic << " J, potential " << potential
      << " J): the motion overflows double precision";
  throw core::SolverError(std::string(stepper.name()), t, n, why.str());
}

}  // namespace

long validate_step_grid(const core::Model& model, double dt,
                        const std::vector<double>& output_times) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    throw std::invalid_argument("the step dt must be positive and finite");
  }
  if (output_times.empty()) throw std::invalid_argument("run_scheme: no output times");
  for (std::size_t k = 0; k < output_times.size(); ++k) {
    if (!std::isfinite(output_times[k]) || (k > 0 && !(output_times[k] > output_times[k - 1]))) {
      throw std::invalid_argument(
          "run_scheme: output times must be finite and strictly increasing");
    }
  }
  const double t0 = output_times.front();
  const double t_end = output_times.back();
  // Resolution first: it also bounds (t_end − t0)/dt, so step_index cannot overflow below.
  const double t_max = std::max(std::abs(t0), std::abs(t_end));
  const double h_min = core::smallest_resolved_step(t_max);
  if (dt < h_min) {
    std::ostringstream out;
    out.precision(3);
    out << "the step dt = " << dt << " s is below what double precision resolves at t = " << t_max
        << " s: the times t0 + n·dt are rounded to "
        << std::numeric_limits<double>::epsilon() * t_max << " s there, so a step must be at least "
        << h_min << " s (1e6 roundings) to be taken as given; use a larger step";
    throw std::invalid_argument(out.str());
  }
  // A step longer than an output interval cannot end on both of its ends; the grid check below
  // would accept it (t − t0 is then 0·dt to within its tolerance), so say it in plain terms.
  if (output_times.size() > 1) {
    double interval = t_end - t0;
    for (std::size_t k = 1; k < output_times.size(); ++k) {
      interval = std::min(interval, output_times[k] - output_times[k - 1]);
    }
    std::ostringstream out;
    out.precision(6);  // the intervals differ by rounding: 0.0999999999999943 prints as 0.1
    if (dt > t_end - t0) {
      out << "the step dt = " << dt << " s is longer than the whole run (" << t_end - t0
          << " s, t = " << t0 << " to " << t_end << "): a step must divide the output interval ("
          << interval << " s)";
      throw std::invalid_argument(out.str());
    }
    // The same relative tolerance as core::is_multiple_of: dt may exceed the interval by rounding.
    if (interval / dt < 1.0 - 1e-9) {
      out << "the step dt = " << dt << " s is longer than the output interval (" << interval
          << " s): a step must divide it";
      throw std::invalid_argument(out.str());
    }
  }
  for (std::size_t k = 1; k < output_times.size(); ++k) {
    require_on_grid("output time", output_times[k], t0, dt);
  }
  for (double d : model.discontinuities()) {
    if (d > t0 && d <= t_end) require_on_grid("load discontinuity", d, t0, dt);
  }
  return step_index(t_end, t0, dt);
}

core::Trajectory run_scheme(const core::Model& model, Stepper& stepper, double dt,
                            const std::vector<double>& output_times,
                            std::atomic<long>* steps_done) {
  const long n_end = validate_step_grid(model, dt, output_times);
  const double t0 = output_times.front();
  if (model.wear_depth_count() > 0 && !stepper.integrates_wear_depth()) {
    throw std::invalid_argument(
        "the method " + std::string(stepper.name()) +
        " does not integrate the contacts' worn depths (docs/wear.md): a scene with a wear law "
        "runs with c1, c2, nmb or genalpha, or with a reference solver");
  }

  core::Trajectory trajectory;
  trajectory.times = output_times;
  trajectory.states.reserve(output_times.size());
  stepper.initialize(t0, model.initial_state());
  // Dissipated work, applied work and wear work by the trapezoidal rule on the step's end
  // rates (second order, like the schemes); one extra evaluation of the dissipative loads per
  // step, only when they exist. Impacts are counted from the gaps after every step.
  const bool track_work = model.tracks_work();
  core::Workspace ws = model.make_workspace();
  // The drives' power needs a constrained solve at every step's end: on the rows of a tracker
  // that follows the accepted steps (core/constraint_tracker.hpp).
  const bool track_joints = track_work && model.tracks_drive_work();
  core::ConstraintTracker tracker = model.make_constraint_tracker();
  const auto count = static_cast<std::size_t>(track_work ? 1 + model.extra_integral_count() : 0);
  std::vector<double> work(count, 0.0);
  std::vector<double> rate(count, 0.0);
  std::vector<double> rate_next(count, 0.0);
  const bool count_impacts = model.wear_channel_count() > 0;
  core::ImpactCounter impacts(model);
  impacts.start(core::LoadContext{t0, t0}, stepper.state(), ws);
  const auto record = [&]() {
    trajectory.states.push_back(stepper.state());
    if (track_work) {
      trajectory.dissipated_work.push_back(work[0]);
      trajectory.extra_work.insert(trajectory.extra_work.end(), work.begin() + 1, work.end());
    }
    if (count_impacts) {
      trajectory.impacts.insert(trajectory.impacts.end(), impacts.counts().begin(),
                                impacts.counts().end());
    }
  };
  if (track_joints) model.advance_tracker(t0, stepper.state(), tracker, ws);
  if (track_work) {
    model.integral_rates(core::LoadContext{t0, t0}, stepper.state(), ws, rate, nullptr, &tracker);
  }
  trajectory.states.clear();
  record();

  check_energy(model, stepper, t0, 0, trajectory.states.back(), ws);
  std::size_t next_output = 1;
  for (long n = 0; n < n_end; ++n) {
    const double t_n = stepper.time();
    const double t_next = t0 + static_cast<double>(n + 1) * dt;
    const StepStatus status = stepper.step(t_next - t_n);
    if (!status.ok) throw core::SolverError(std::string(stepper.name()), t_n, n, status.message);
    if (!detail::all_finite(stepper.state())) {
      throw core::SolverError(std::string(stepper.name()), t_n, n,
                              "the step left a non-finite state (inf or NaN): the motion "
                              "diverged or overflowed double precision");
    }
    const double t_np1 = stepper.time();
    const core::LoadContext end_context{t_np1, 0.5 * (t_n + t_np1)};
    if (track_work) {
      if (track_joints) model.advance_tracker(t_np1, stepper.state(), tracker, ws);
      model.integral_rates(end_context, stepper.state(), ws, rate_next, nullptr, &tracker);
      for (std::size_t j = 0; j < count; ++j) {
        work[j] += 0.5 * (t_np1 - t_n) * (rate[j] + rate_next[j]);
      }
      std::swap(rate, rate_next);
    }
    if (count_impacts) impacts.update(end_context, stepper.state(), ws);
    if (steps_done != nullptr) steps_done->store(n + 1, std::memory_order_relaxed);
    while (next_output < output_times.size() &&
           step_index(output_times[next_output], t0, dt) == n + 1) {
      check_energy(model, stepper, output_times[next_output], n, stepper.state(), ws);
      for (std::size_t j = 0; j < count; ++j) {
        if (!std::isfinite(work[j])) {
          throw core::SolverError(std::string(stepper.name()), output_times[next_output], n,
                                  j == 0 ? "the dissipated work is not finite"
                                         : "an accumulated work (applied or wear) is not finite");
        }
      }
      record();
      ++next_output;
    }
  }
  return trajectory;
}

}  // namespace flexref::lie
