/// \file odeint_solver.cpp
/// Boost.Odeint's controlled Runge–Kutta–Fehlberg 7(8) on the quasi-velocity ODE form
/// (reference/ode_form.hpp): the independent cross-check of the two SUNDIALS drivers
/// (docs/design/schemes.md, "Reference integrators"). It shares nothing with them but the model and the
/// ODE form: its own segment plan, stepping loop, output and failure handling.
///
/// - Error control: odeint's default checker, err_i / (atol + rtol (|x_i| + h |x'_i|)) ≤ 1 in
///   the max norm, step-size adjustment by odeint (make_controlled(atol, rtol, ...)).
/// - No interpolation: the loop truncates the step to land exactly on every output time and
///   on every known load discontinuity; each segment between discontinuities evaluates its
///   loads with t_segment = the segment's midpoint.
/// - The Euler parameters are renormalized at every output and segment end (a one-step method
///   carries no history, so this projection costs only the derivative at the projected state).
/// - Switching functions (contact gaps, core::Model::switching_functions) are evaluated after
///   every accepted step; when one changes sign, the step is bisected on its length, re-taking
///   the RKF7(8) step from the accepted start each time (no interpolation: the step's own
///   solution, as accurate as the accepted step), down to a few ulp of t, and the step ends
///   just past the zero. The event time is recorded; no step straddles a contact onset or
///   release. (The design allows bisection on dense output; RKF7(8) has none, and re-stepping
///   is exact to the step's accuracy.)
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
#include "reference/ode_form.hpp"
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
  SegmentRhs(const reference::OdeForm& form, reference::OdeForm::Scratch& scratch,
             Counters& counters, double t_segment)
      : form_(&form), scratch_(&scratch), counters_(&counters), t_segment_(t_segment) {}

  void operator()(const StateVector& x, StateVector& dxdt, double t) const {
    ++counters_->rhs_evaluations;
    form_->rhs(core::LoadContext{t, t_segment_}, x.data(), dxdt.data(), *scratch_);
    if (!all_finite(dxdt)) counters_->nonfinite = true;
  }

 private:
  const reference::OdeForm* form_;
  reference::OdeForm::Scratch* scratch_;
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
  Integrator(const reference::OdeForm& form, const SolverOptions& options, SolverStats& stats)
      : form_(&form),
        options_(options),
        stats_(&stats),
        scratch_(form.make_scratch()),
        stepper_(
            odeint::make_controlled(options.absolute_tolerance(), options.rtol, ErrorStepper())),
        x_(static_cast<std::size_t>(form.size())),
        x_new_(x_.size()),
        x_mid_(x_.size()),
        dxdt_(x_.size()),
        g_(static_cast<std::size_t>(form.model().switching_function_count())),
        g_new_(g_.size()),
        g_mid_(g_.size()) {}

  /// Where located event times are appended.
  void record_events_in(std::vector<double>* events) { events_ = events; }

  double time() const { return t_; }

  /// Starts a segment at the current time: the loads switch to the branch at t_segment.
  void begin_segment(const core::State& state, double t_segment) {
    t_segment_ = t_segment;
    const double work = form_->dissipated_work(x_.data());  // carried across segments
    form_->pack(state, x_.data());
    form_->set_dissipated_work(x_.data(), work);
    evaluate_derivative();
    evaluate_switching(x_, t_, g_);
    if (dt_ <= 0.0) dt_ = initial_step(x_, dxdt_, options_.rtol, options_.absolute_tolerance());
  }

  /// Steps to exactly `target`, truncating the last step to land on it.
  void advance_to(double target) {
    long steps_here = 0;
    while (t_ < target) {
      const double remaining = target - t_;
      // Land when the proposal reaches the target or would leave a sliver of a few ulp.
      // Never step far past a switch: the trial is capped at twice the time to the nearest
      // zero of a switching function at its current rate, so a step that reaches a contact
      // ends on its other side (where the sign test sees it) instead of passing through.
      const double proposal = std::min(dt_, switching_step_cap(dt_));
      const bool lands = proposal >= remaining - time_slack(target);
      const double h = lands ? remaining : proposal;
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
      double t_new = lands ? target : t_trial;
      if (!g_.empty()) {
        evaluate_switching(x_new_, t_new, g_new_);
        bool crossed = sign_changed(g_, g_new_);
        if (!crossed) {
          // Both ends on the same side: a gap can still dip through zero and back within the
          // step (a short contact inside a long flight step). Check the quadratic through g
          // and ġ at the start and g at the end; if its extremum is on the other side, step
          // to it and look there.
          const double s_candidate = double_crossing_candidate(t_new - t_);
          if (s_candidate > 0.0) {
            const double h_candidate = s_candidate * (t_new - t_);
            stepper_.stepper().do_step(SegmentRhs(*form_, scratch_, counters_, t_segment_), x_,
                                       dxdt_, t_, x_mid_, h_candidate);
            evaluate_switching(x_mid_, t_ + h_candidate, g_mid_);
            if (sign_changed(g_, g_mid_)) {
              std::swap(x_new_, x_mid_);
              std::swap(g_new_, g_mid_);
              t_new = t_ + h_candidate;
              crossed = true;
            }
          }
        }
        if (crossed) {
          // Bisect the step length: x_new_ becomes the solution just past the zero.
          t_new = t_ + locate_event(t_new - t_);
          if (events_ != nullptr) events_->push_back(t_new);
          ++stats_->events;
        }
        std::swap(g_, g_new_);
      }
      std::swap(x_, x_new_);
      const bool landed = t_new == target;
      t_ = t_new;
      // A truncated landing step does not shrink the next proposal.
      dt_ = landed && h < dt_ ? std::max(dt_, h_next) : h_next;
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
    evaluate_switching(x_, t_, g_);
  }

  void unpack(core::State& state) const { form_->unpack(time(), x_.data(), state); }
  double dissipated_work() const { return form_->dissipated_work(x_.data()); }
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

  void evaluate_switching(const StateVector& x, double t, std::vector<double>& g) {
    if (g.empty()) return;
    form_->unpack(t, x.data(), scratch_.state);
    form_->model().switching_functions(core::LoadContext{t, t_segment_}, scratch_.state,
                                       scratch_.workspace, g);
  }

  /// Some switching function changed side (positive ↔ not positive).
  static bool sign_changed(const std::vector<double>& a, const std::vector<double>& b) {
    for (std::size_t k = 0; k < a.size(); ++k) {
      if ((a[k] > 0.0) != (b[k] > 0.0)) return true;
    }
    return false;
  }

  /// 2 min_k |g_k| / |ġ_k| over the functions moving towards zero (ġ by a forward difference
  /// along dxdt_), or `h` when none is.
  double switching_step_cap(double h) {
    if (g_.empty()) return h;
    const double delta = 1e-7 * h;
    for (std::size_t i = 0; i < x_.size(); ++i) x_mid_[i] = x_[i] + delta * dxdt_[i];
    evaluate_switching(x_mid_, t_ + delta, g_mid_);
    double cap = h;
    for (std::size_t k = 0; k < g_.size(); ++k) {
      const double rate = (g_mid_[k] - g_[k]) / delta;
      if (g_[k] != 0.0 && rate != 0.0 && (g_[k] > 0.0) != (rate > 0.0)) {
        cap = std::min(cap, 2.0 * std::abs(g_[k] / rate));
      }
    }
    return cap;
  }

  /// For a step of length h from (t_, x_) whose switching functions end on the side they
  /// started (g_ → g_new_): the fraction s ∈ (0, 1) of the step where the quadratic through
  /// g(0), ġ(0) and g(h) reaches its extremum on the other side of zero (the smallest over the
  /// functions), or 0 when no quadratic does. ġ(0) = ∇g · ẋ by a forward difference along
  /// dxdt_ (one extra switching evaluation, no right-hand side).
  double double_crossing_candidate(double h) {
    const double delta = 1e-7 * h;
    for (std::size_t i = 0; i < x_.size(); ++i) x_mid_[i] = x_[i] + delta * dxdt_[i];
    evaluate_switching(x_mid_, t_ + delta, g_mid_);
    double best = 0.0;
    for (std::size_t k = 0; k < g_.size(); ++k) {
      const double slope = (g_mid_[k] - g_[k]) / delta * h;  // dg/ds
      const double curvature = g_new_[k] - g_[k] - slope;    // q(s) = g0 + slope s + c s²
      if (curvature == 0.0) continue;
      const double s_star = -slope / (2.0 * curvature);
      if (!(s_star > 0.0 && s_star < 1.0)) continue;
      const double extremum = g_[k] - slope * slope / (4.0 * curvature);
      if ((extremum > 0.0) != (g_[k] > 0.0) && (best == 0.0 || s_star < best)) best = s_star;
    }
    return best;
  }

  /// Smallest step length (to a few ulp of t) from (t_, x_) after which a switching function
  /// has changed side; x_new_ and g_new_ hold the state there. `h` is a step known to cross.
  double locate_event(double h) {
    double lo = 0.0;
    double hi = h;
    const double resolution =
        4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t_));
    for (int k = 0; k < 200 && hi - lo > resolution; ++k) {
      const double mid = 0.5 * (lo + hi);
      stepper_.stepper().do_step(SegmentRhs(*form_, scratch_, counters_, t_segment_), x_, dxdt_, t_,
                                 x_mid_, mid);
      evaluate_switching(x_mid_, t_ + mid, g_mid_);
      if (sign_changed(g_, g_mid_)) {
        hi = mid;
        std::swap(x_new_, x_mid_);
        std::swap(g_new_, g_mid_);
      } else {
        lo = mid;
      }
    }
    return hi;
  }

  void reject(double dt, const char* why) {
    ++stats_->error_test_failures;
    dt_ = dt;
    if (!(dt_ > 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t_)))) {
      throw core::SolverError("odeint", t_, stats_->steps, why);
    }
  }

  const reference::OdeForm* form_;
  SolverOptions options_;
  SolverStats* stats_;
  reference::OdeForm::Scratch scratch_;
  Counters counters_;
  ControlledStepper stepper_;
  StateVector x_, x_new_, x_mid_, dxdt_;
  std::vector<double> g_, g_new_, g_mid_;  ///< switching functions at x_, x_new_, x_mid_
  std::vector<double>* events_ = nullptr;
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
  const reference::OdeForm form(model);

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
  const bool track_work = form.work_index() >= 0;
  for (; k < output_times.size() && output_times[k] <= time_slack(0.0); ++k) {
    run.trajectory.states.push_back(state);
    if (track_work) run.trajectory.dissipated_work.push_back(0.0);
  }
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
      for (; k < output_times.size() && output_times[k] <= end + time_slack(end); ++k) {
        tic = std::clock();
        integrator.advance_to(std::min(output_times[k], end));
        integrator.normalize();
        cpu += std::clock() - tic;
        integrator.unpack(state);
        run.trajectory.states.push_back(state);
        if (track_work) run.trajectory.dissipated_work.push_back(integrator.dissipated_work());
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
