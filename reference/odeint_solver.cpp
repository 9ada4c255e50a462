/// \file odeint_solver.cpp
/// Boost.Odeint's controlled Runge–Kutta–Fehlberg 7(8) on the quasi-velocity ODE form
/// (core/ode_form.hpp): the independent cross-check of the two SUNDIALS drivers (design/
/// schemes.md, "Reference integrators"). It shares nothing with them but the model and the
/// ODE form: its own segment plan, stepping loop, output and failure handling.
///
/// - Error control: odeint's default checker, err_i / (atol + rtol (|x_i| + h |x'_i|)) ≤ 1 in
///   the max norm, step-size adjustment by odeint (make_controlled(atol, rtol, ...)).
/// - No interpolation: the loop truncates the step to land exactly on every output time and
///   on every known load discontinuity; each segment between discontinuities evaluates its
///   loads with t_segment = the segment's midpoint.
/// - The Euler parameters are renormalized at every output and segment end (a one-step method
///   carries no history, so this projection costs only the derivative at the projected state).
/// - SolverOptions::max_steps bounds the steps between two consecutive output times, as it
///   does for IDA and CVODE (mxstep).
#include <algorithm>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <cmath>
#include <cstddef>
#include <ctime>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/ode_form.hpp"
#include "reference/reference_solver.hpp"

namespace flexref::reference {
namespace {

namespace odeint = boost::numeric::odeint;

using StateVector = std::vector<double>;
using ErrorStepper = odeint::runge_kutta_fehlberg78<StateVector>;
using ControlledStepper = odeint::controlled_runge_kutta<ErrorStepper>;

/// Times closer than this to a segment boundary or output time are taken as it: a few ulp.
double time_slack(double t) {
  return 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
}

bool all_finite(const StateVector& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

struct Counters {
  long rhs_evaluations = 0;
  bool nonfinite = false;  ///< set when an evaluation returned a non-finite derivative
};

/// The ODE form as an odeint system on one segment: counts evaluations and flags non-finite
/// derivatives (odeint's max-norm error check would let a NaN through). Copied by odeint, so
/// it holds pointers; allocates nothing.
class SegmentRhs {
 public:
  SegmentRhs(const core::OdeForm& form, core::OdeForm::Scratch& scratch, Counters& counters,
             double t_segment)
      : form_(&form), scratch_(&scratch), counters_(&counters), t_segment_(t_segment) {}

  void operator()(const StateVector& x, StateVector& dxdt, double t) const {
    ++counters_->rhs_evaluations;
    form_->rhs(core::LoadContext{t, t_segment_}, x.data(), dxdt.data(), *scratch_);
    if (!all_finite(dxdt)) counters_->nonfinite = true;
  }

 private:
  const core::OdeForm* form_;
  core::OdeForm::Scratch* scratch_;
  Counters* counters_;
  double t_segment_;
};

/// Starting step of Hairer, Nørsett & Wanner (Solving ODEs I, II.4): 1 % of |x|/|x'| in the
/// error-weighted RMS norm, so the first trial is neither absurdly small nor large.
double initial_step(const StateVector& x, const StateVector& dxdt, double rtol, double atol) {
  double d0 = 0.0, d1 = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double scale = atol + rtol * std::abs(x[i]);
    d0 += (x[i] / scale) * (x[i] / scale);
    d1 += (dxdt[i] / scale) * (dxdt[i] / scale);
  }
  if (d0 < 1e-10 || d1 < 1e-10) return 1e-6;
  return 0.01 * std::sqrt(d0 / d1);
}

class Integrator {
 public:
  Integrator(const core::OdeForm& form, const SolverOptions& options, SolverStats& stats)
      : form_(&form),
        options_(options),
        stats_(&stats),
        scratch_(form.make_scratch()),
        stepper_(
            odeint::make_controlled(options.absolute_tolerance(), options.rtol, ErrorStepper())),
        x_(static_cast<std::size_t>(form.size())),
        x_new_(x_.size()),
        dxdt_(x_.size()) {}

  double time() const { return t_; }

  /// Starts a segment at the current time: the loads switch to the branch at t_segment.
  void begin_segment(const core::State& state, double t_segment) {
    t_segment_ = t_segment;
    form_->pack(state, x_.data());
    evaluate_derivative();
    if (dt_ <= 0.0) dt_ = initial_step(x_, dxdt_, options_.rtol, options_.absolute_tolerance());
  }

  /// Steps to exactly `target`, truncating the last step to land on it.
  void advance_to(double target) {
    long steps_here = 0;
    while (t_ < target) {
      const double remaining = target - t_;
      // Land when the proposal reaches the target or would leave a sliver of a few ulp.
      const bool lands = dt_ >= remaining - time_slack(target);
      const double h = lands ? remaining : dt_;
      double t_trial = t_;
      double h_next = h;
      counters_.nonfinite = false;
      const odeint::controlled_step_result result = stepper_.try_step(
          SegmentRhs(*form_, scratch_, counters_, t_segment_), x_, dxdt_, t_trial, x_new_, h_next);
      if (counters_.nonfinite || !all_finite(x_new_)) {
        // A trial stage reached a singular load: reject and retry a quarter of the step.
        reject(0.25 * h, "a trial step produced a non-finite right-hand side or state");
        continue;
      }
      if (result == odeint::fail) {
        reject(h_next, "the step size fell below round-off (error test failures)");
        continue;
      }
      std::swap(x_, x_new_);
      t_ = lands ? target : t_trial;
      // A truncated landing step does not shrink the next proposal.
      dt_ = lands && h < dt_ ? std::max(dt_, h_next) : h_next;
      ++stats_->steps;
      if (++steps_here > options_.max_steps) {
        throw core::SolverError("odeint", t_, stats_->steps,
                                "more than max_steps = " + std::to_string(options_.max_steps) +
                                    " steps between output times (too much work)");
      }
      evaluate_derivative();
    }
  }

  /// Projects θ onto the unit sphere (at outputs and segment ends).
  void normalize() {
    form_->normalize_euler_parameters(x_.data());
    evaluate_derivative();
  }

  void unpack(core::State& state) const { form_->unpack(time(), x_.data(), state); }
  long rhs_evaluations() const { return counters_.rhs_evaluations; }

 private:
  void evaluate_derivative() {
    counters_.nonfinite = false;
    SegmentRhs(*form_, scratch_, counters_, t_segment_)(x_, dxdt_, t_);
    if (counters_.nonfinite) {
      // The derivative at an accepted state does not depend on the step: no step can help.
      throw core::SolverError("odeint", t_, stats_->steps,
                              "the right-hand side is not finite at the current state");
    }
  }

  void reject(double dt, const char* why) {
    ++stats_->error_test_failures;
    dt_ = dt;
    if (!(dt_ > 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t_)))) {
      throw core::SolverError("odeint", t_, stats_->steps, why);
    }
  }

  const core::OdeForm* form_;
  SolverOptions options_;
  SolverStats* stats_;
  core::OdeForm::Scratch scratch_;
  Counters counters_;
  ControlledStepper stepper_;
  StateVector x_, x_new_, dxdt_;
  double t_ = 0.0;
  double dt_ = 0.0;  ///< proposal for the next step; 0 before the first segment
  double t_segment_ = 0.0;
};

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
  const core::OdeForm form(model);

  ReferenceRun run;
  run.solver = "odeint";
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
  for (; k < output_times.size() && output_times[k] <= time_slack(0.0); ++k) {
    run.trajectory.states.push_back(state);
  }
  if (k == output_times.size()) return run;

  Integrator integrator(form, options, run.stats);
  std::clock_t cpu = 0;
  try {
    double start = 0.0;
    for (double end : ends) {
      std::clock_t tic = std::clock();
      integrator.begin_segment(state, 0.5 * (start + end));
      cpu += std::clock() - tic;
      for (; k < output_times.size() && output_times[k] <= end + time_slack(end); ++k) {
        tic = std::clock();
        integrator.advance_to(std::min(output_times[k], end));
        integrator.normalize();
        cpu += std::clock() - tic;
        integrator.unpack(state);
        run.trajectory.states.push_back(state);
      }
      if (integrator.time() < end) {
        tic = std::clock();
        integrator.advance_to(end);
        integrator.normalize();
        cpu += std::clock() - tic;
        integrator.unpack(state);
      }
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
