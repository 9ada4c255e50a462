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
#include <array>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <cmath>
#include <cstddef>
#include <ctime>
#include <exception>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/impact_counter.hpp"
#include "reference/continuous_extension.hpp"
#include "reference/integral_weights.hpp"
#include "reference/method_choice.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/solve_progress.hpp"
#include "reference/switching_predictor.hpp"

namespace flexref::reference {
namespace {

namespace odeint = boost::numeric::odeint;

using StateVector = std::vector<double>;
using ErrorStepper = odeint::runge_kutta_fehlberg78<StateVector>;

/// The integral components' tolerance (reference/integral_weights.hpp): divided by `factor`,
/// the steps since the segment start, and not below 100 round-offs of the value.
struct IntegralScaling {
  IntegralComponents integrals;
  double factor = 1.0;
  /// The tolerance `tol` of component i at value x.
  double tolerance(std::size_t i, double tol, double x) const {
    const auto k = static_cast<int>(i);
    if (k < integrals.first || k >= integrals.first + integrals.count) return tol;
    return std::max(tol / factor, 100.0 * std::numeric_limits<double>::epsilon() * std::abs(x));
  }
};

/// odeint's default error checker, max_i |err_i| / (atol + rtol (|x_i| + h |ẋ_i|)), with the
/// integral components' tolerances scaled (IntegralScaling).
class IntegralErrorChecker {
 public:
  using value_type = double;
  using algebra_type = ErrorStepper::algebra_type;
  using operations_type = ErrorStepper::operations_type;

  IntegralErrorChecker(double atol, double rtol, const IntegralScaling* scaling)
      : atol_(atol), rtol_(rtol), scaling_(scaling) {}

  template <class State, class Deriv, class Err, class Time>
  double error(const State& x_old, const Deriv& dxdt_old, Err& x_err, Time dt) const {
    double largest = 0.0;
    for (std::size_t i = 0; i < x_old.size(); ++i) {
      const double tol = scaling_->tolerance(
          i, atol_ + rtol_ * (std::abs(x_old[i]) + std::abs(dt) * std::abs(dxdt_old[i])), x_old[i]);
      largest = std::max(largest, std::abs(x_err[i]) / tol);
    }
    return largest;
  }
  template <class State, class Deriv, class Err, class Time>
  double error(algebra_type& /*algebra*/, const State& x_old, const Deriv& dxdt_old, Err& x_err,
               Time dt) const {
    return error(x_old, dxdt_old, x_err, dt);
  }

 private:
  double atol_;
  double rtol_;
  const IntegralScaling* scaling_;
};

using ControlledStepper = odeint::controlled_runge_kutta<ErrorStepper, IntegralErrorChecker>;

/// Times closer than this to a segment boundary or output time are taken as it: a few ulp.
double time_slack(double t) {
  return 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
}

bool all_finite(const StateVector& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

/// Some switching function changed side (positive ↔ not positive).
bool sign_changed(const std::vector<double>& a, const std::vector<double>& b) {
  for (std::size_t k = 0; k < a.size(); ++k) {
    if ((a[k] > 0.0) != (b[k] > 0.0)) return true;
  }
  return false;
}

struct Counters {
  long rhs_evaluations = 0;
  bool nonfinite = false;  ///< set when an evaluation returned a non-finite derivative
  /// Set when a watched evaluation's switching functions were on another side than the step
  /// start's (SegmentRhs::watch).
  bool other_side = false;
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
    if (start_side_ == nullptr) return;
    form_->unpack(t, x.data(), scratch_->state);
    form_->model().switching_functions(core::LoadContext{t, t_segment_}, scratch_->state,
                                       scratch_->workspace, *stage_side_);
    if (sign_changed(*start_side_, *stage_side_)) counters_->other_side = true;
  }

  /// Also evaluates the switching functions at every evaluation (into `scratch`, sized) and
  /// sets Counters::other_side when one is on another side than in `start`.
  SegmentRhs watch(const std::vector<double>& start, std::vector<double>& scratch) const {
    SegmentRhs watched = *this;
    watched.start_side_ = &start;
    watched.stage_side_ = &scratch;
    return watched;
  }

 private:
  const reference::OdeForm* form_;
  reference::OdeForm::Scratch* scratch_;
  Counters* counters_;
  double t_segment_;
  const std::vector<double>* start_side_ = nullptr;
  std::vector<double>* stage_side_ = nullptr;
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
        scaling_{{form.depth_index(), form.depth_count() + form.integral_count()}, 1.0},
        stepper_(IntegralErrorChecker(options.absolute_tolerance(), options.rtol, &scaling_)),
        x_(static_cast<std::size_t>(form.size())),
        x_new_(x_.size()),
        x_mid_(x_.size()),
        dxdt_(x_.size()),
        dxdt_mid_(x_.size()),
        x_near_(x_.size()),
        dxdt_near_(x_.size()),
        predictor_(form),
        x_previous_(x_.size()),
        dxdt_previous_(x_.size()),
        x_node1_(x_.size()),
        dxdt_node1_(x_.size()),
        x_node2_(x_.size()),
        dxdt_node2_(x_.size()),
        x_output_(x_.size()),
        extension_(form.size()),
        g_(static_cast<std::size_t>(form.model().switching_function_count())),
        g_new_(g_.size()),
        g_mid_(g_.size()),
        g_stage_(g_.size()),
        carried_(static_cast<std::size_t>(form.integral_count())),
        tracker_(form.model().make_constraint_tracker()) {
    scratch_.tracker = &tracker_;
  }

  /// Where located event times are appended.
  void record_events_in(std::vector<double>* events) { events_ = events; }

  double time() const { return t_; }

  /// Starts a segment at the current time: the loads switch to the branch at t_segment.
  void begin_segment(const core::State& state, double t_segment) {
    t_segment_ = t_segment;
    works_.values(x_.data(), carried_);  // W_d and the extra integrals, across segments
    form_->pack(state, x_.data());
    // Ideal joints: every segment starts on the constraint manifold, where the joints' tracker
    // moves.
    if (form_->model().has_constraints()) {
      form_->project(t_, x_.data(), scratch_);
      form_->unpack(t_, x_.data(), scratch_.state);
      form_->model().advance_tracker(t_, scratch_.state, tracker_, scratch_.workspace);
    }
    works_.start(carried_, x_.data());
    scaling_.factor = 1.0;
    evaluate_derivative();
    evaluate_switching(x_, t_, g_);
    t_previous_ = t_;
    extension_fitted_ = false;
    if (dt_ <= 0.0) dt_ = initial_step(x_, dxdt_, options_.rtol, options_.absolute_tolerance());
  }

  /// One accepted step from the current time, truncated to land exactly on `end` (the segment
  /// end) and ended just past a located event. Keeps the step's start for output().
  void step(double end) {
    for (;;) {
      const double remaining = end - t_;
      // Land when the proposal reaches the end or would leave a sliver of a few ulp. Never
      // step far past a switch (switching_step_cap).
      // The cap near a switch never goes below a few ulp of t (a step must move t).
      const double proposal = std::min(dt_, std::max(switching_step_cap(dt_), time_slack(t_)));
      const bool lands = proposal >= remaining - time_slack(end);
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
      if (in_contact() && !halves_agree(h, h_next)) {
        reject(h_next, "the step size fell below round-off (contact step-doubling test)");
        continue;
      }
      double t_new = lands ? end : t_trial;
      if (!g_.empty()) {
        evaluate_switching(x_new_, t_new, g_new_);
        bool crossed = sign_changed(g_, g_new_);
        if (!crossed) {
          // Both ends on the same side: a gap can still dip through zero and back within the
          // step. Step to where it may have (double_crossing_candidates) and look there.
          for (const double s_candidate : double_crossing_candidates(t_new - t_)) {
            if (s_candidate <= 0.0) continue;
            const double h_candidate = s_candidate * (t_new - t_);
            stepper_.stepper().do_step(SegmentRhs(*form_, scratch_, counters_, t_segment_), x_,
                                       dxdt_, t_, x_mid_, h_candidate);
            evaluate_switching(x_mid_, t_ + h_candidate, g_mid_);
            if (sign_changed(g_, g_mid_)) {
              std::swap(x_new_, x_mid_);
              std::swap(g_new_, g_mid_);
              t_new = t_ + h_candidate;
              crossed = true;
              break;
            }
          }
        }
        if (crossed) {
          // Bisect the step length: x_new_ becomes the solution just past the zero, or, when
          // rounding leaves it on the near side, just before it (the next step crosses).
          const auto [length, switched] = locate_event(t_new - t_);
          t_new = t_ + length;
          ended_at_event_ = switched;
          if (switched) {
            if (events_ != nullptr) events_->push_back(t_new);
            ++stats_->events;
          }
        } else {
          ended_at_event_ = false;
        }
        std::swap(g_, g_new_);
      }
      // The accepted step [t_previous_, t_]: keep its start for the continuous extension.
      std::swap(x_previous_, x_);
      std::swap(dxdt_previous_, dxdt_);
      std::swap(x_, x_new_);
      t_previous_ = t_;
      t_ = t_new;
      extension_fitted_ = false;
      const bool landed = t_new == end;
      // A truncated landing step does not shrink the next proposal.
      dt_ = landed && h < dt_ ? std::max(dt_, h_next) : h_next;
      ++stats_->steps;
      scaling_.factor += 1.0;  // the steps since the segment start, for the next step's test
      if (++steps_since_output_ > options_.max_steps) {
        throw core::SolverError("odeint", t_, stats_->steps,
                                "more than max_steps = " + std::to_string(options_.max_steps) +
                                    " steps between output times (too much work)");
      }
      evaluate_derivative();
      return;
    }
  }

  /// The state at an output time t in [start of the last step, time()]: the step's end value
  /// at its end; inside, when it is the step's only output, an RKF7(8) step of length
  /// t − start from the step's start (12 evaluations), else the continuous extension (fitted
  /// once per step, 26 evaluations). Both are of the method's order; the first halves the cost
  /// of dense-output scenes whose steps hold about one output each (flexible_spinner at rtol
  /// 1e-12: 1022 steps for 1000 outputs). The output is a state of the integration: the joints'
  /// tracker moves there.
  void output(double t, core::State& state, bool only_output_inside) {
    steps_since_output_ = 0;
    double t_state = t_;
    if (t >= t_ - time_slack(t_)) {
      form_->unpack(t_, x_.data(), state);
    } else {
      if (only_output_inside) {
        stepper_.stepper().do_step(SegmentRhs(*form_, scratch_, counters_, t_segment_), x_previous_,
                                   dxdt_previous_, t_previous_, x_output_, t - t_previous_);
      } else {
        if (!extension_fitted_) fit_extension();
        extension_.evaluate(t, x_output_.data());
      }
      t_state = t;
      form_->unpack(t, x_output_.data(), state);
    }
    const core::Model& model = form_->model();
    if (model.has_constraints())
      model.advance_tracker(t_state, state, tracker_, scratch_.workspace);
  }
  /// W_d and the extra integrals at the output t just computed by output().
  void output_integrals(double t, std::span<double> out) const {
    if (t >= t_ - time_slack(t_)) {
      works_.values(x_.data(), out);
    } else {
      works_.values(x_output_.data(), out);  // the values output(t) just interpolated
    }
  }

  /// Projects θ onto the unit sphere (at segment ends).
  void normalize() {
    form_->normalize_euler_parameters(x_.data());
    evaluate_derivative();
    evaluate_switching(x_, t_, g_);
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

  void evaluate_switching(const StateVector& x, double t, std::vector<double>& g) {
    if (g.empty()) return;
    form_->unpack(t, x.data(), scratch_.state);
    form_->model().switching_functions(core::LoadContext{t, t_segment_}, scratch_.state,
                                       scratch_.workspace, g);
  }

  /// Some switching function is not positive at the step's start: a contact is engaged.
  bool in_contact() const {
    return std::any_of(g_.begin(), g_.end(), [](double g) { return !(g > 0.0); });
  }

  /// The step-doubling test of a step taken in contact (x_new_ after h from x_): RKF7(8)'s own
  /// error estimate, 41/840 (k1 + k11 − k12 − k13) h, compares only the stages at the step's ends
  /// and accepts a step across a whole stiff contact phase (measured on bouncing_ball: a 0.011 s
  /// step from an impact's onset through its compression, in error by millimetres, passed it).
  /// Two steps of h/2 must agree with the step in odeint's own error norm,
  /// max_i |Δ_i| / (atol + rtol (|x_i| + h |ẋ_i|)) ≤ 1; the difference estimates the step's
  /// local error (1 − 2⁻⁸ of it). On failure h_next is the order-8 controller's proposal.
  bool halves_agree(double h, double& h_next) {
    SegmentRhs rhs(*form_, scratch_, counters_, t_segment_);
    stepper_.stepper().do_step(rhs, x_, dxdt_, t_, x_mid_, 0.5 * h);
    rhs(x_mid_, dxdt_mid_, t_ + 0.5 * h);
    stepper_.stepper().do_step(rhs, x_mid_, dxdt_mid_, t_ + 0.5 * h, x_output_, 0.5 * h);
    const double rtol = options_.rtol;
    const double atol = options_.absolute_tolerance();
    double error = 0.0;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      const double scale =
          scaling_.tolerance(i, atol + rtol * (std::abs(x_[i]) + h * std::abs(dxdt_[i])), x_[i]);
      error = std::max(error, std::abs(x_output_[i] - x_new_[i]) / scale);
    }
    if (!(error <= 1.0)) {
      // h (0.9 / error)^(1/8), at least a fifth of h (odeint's controller's bounds).
      h_next =
          std::isfinite(error) ? h * std::max(0.2, 0.9 * std::pow(error, -1.0 / 8.0)) : 0.2 * h;
      return false;
    }
    return true;
  }

  /// SwitchingPredictor's cap on a step of length h from the current state.
  double switching_step_cap(double h) {
    if (g_.empty()) return h;
    return predictor_.cap(
        t_, x_.data(), dxdt_.data(), g_, h, t_segment_,
        [this](double t, const double* x, double* xdot) {
          const std::size_t n = x_.size();
          std::copy(x, x + n, x_mid_.begin());
          counters_.nonfinite = false;
          SegmentRhs(*form_, scratch_, counters_, t_segment_)(x_mid_, dxdt_mid_, t);
          std::copy(dxdt_mid_.begin(), dxdt_mid_.end(), xdot);
          return !counters_.nonfinite;
        },
        scratch_);
  }

  /// For a step of length h from (t_, x_) whose switching functions end on the side they
  /// started (g_ → g_new_): where in the step a function may have dipped through zero and back,
  /// as fractions s ∈ (0, 1), ascending (0 where there is no candidate):
  ///  - the extremum of the quadratic through g(0), ġ(0) and g(h), when it lies on the other side
  ///    of zero (a short contact inside a long flight step);
  ///  - the zero of the linear model g(0) + ġ(0) t, when it lies inside the step: a stiff
  ///    contact can throw the body back out within one step, and RKF7(8)'s error estimate,
  ///    41/840 (k1 + k11 − k12 − k13) h, need not see the stages that were inside it (measured
  ///    on bouncing_ball with tolerance-sized steps of 0.06 s: the first impact was stepped over
  ///    and the ball gained 2 m of height); the end value, already thrown back, hides it from the
  ///    quadratic.
  /// The smallest over the functions of each. ġ(0) = ∇g · ẋ by a forward difference along dxdt_
  /// (one extra switching evaluation, no right-hand side).
  std::array<double, 2> double_crossing_candidates(double h) {
    const double delta = 1e-7 * h;
    for (std::size_t i = 0; i < x_.size(); ++i) x_mid_[i] = x_[i] + delta * dxdt_[i];
    evaluate_switching(x_mid_, t_ + delta, g_mid_);
    double quadratic = 0.0;
    double linear = 0.0;
    for (std::size_t k = 0; k < g_.size(); ++k) {
      const double slope = (g_mid_[k] - g_[k]) / delta * h;  // dg/ds
      if (slope != 0.0 && g_[k] != 0.0 && (slope > 0.0) != (g_[k] > 0.0)) {
        const double s_zero = -g_[k] / slope;
        if (s_zero < 1.0 && (linear == 0.0 || s_zero < linear)) linear = s_zero;
      }
      const double curvature = g_new_[k] - g_[k] - slope;  // q(s) = g0 + slope s + c s²
      if (curvature == 0.0) continue;
      const double s_star = -slope / (2.0 * curvature);
      if (!(s_star > 0.0 && s_star < 1.0)) continue;
      const double extremum = g_[k] - slope * slope / (4.0 * curvature);
      if ((extremum > 0.0) != (g_[k] > 0.0) && (quadratic == 0.0 || s_star < quadratic)) {
        quadratic = s_star;
      }
    }
    if (quadratic == 0.0 || (linear != 0.0 && linear < quadratic)) return {linear, quadratic};
    return {quadratic, linear};
  }

  /// The first switch in a step of length h from (t_, x_) known to cross, located to a few ulp
  /// of t by bisection on the step length, re-taking the RKF7(8) step from the start each time.
  /// A trial counts as past the switch when its end *or any of its evaluations* is on another
  /// side than the start: the stages near the end of a step onto the switch lie a local error
  /// away from the trajectory, on either side of it, and a penalty law with damping jumps at
  /// the onset (F = c δ̇ at δ = 0), so one such stage would add ~b_i h c δ̇ / m to the step,
  /// however small the tolerance (measured: 2e-3 m/s on hinged_spinner_strike's block,
  /// 0.023 J of W_d). The state past the switch is then one clean step to the bracket's near
  /// end and one step across it (a few ulp long: its branch error is negligible). Returns the
  /// step length and whether the state there (x_new_, g_new_) is past the switch; the near
  /// side's derivative is kept in dxdt_near_ (the left limit at the step's end, for the
  /// continuous extension).
  std::pair<double, bool> locate_event(double h) {
    double lo = 0.0;
    double hi = h;
    const double resolution =
        4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t_));
    const SegmentRhs rhs(*form_, scratch_, counters_, t_segment_);
    const SegmentRhs watched = rhs.watch(g_, g_stage_);
    for (int k = 0; k < 200 && hi - lo > resolution; ++k) {
      const double mid = 0.5 * (lo + hi);
      counters_.other_side = false;
      stepper_.stepper().do_step(watched, x_, dxdt_, t_, x_mid_, mid);
      evaluate_switching(x_mid_, t_ + mid, g_mid_);
      if (counters_.other_side || sign_changed(g_, g_mid_)) {
        hi = mid;
      } else {
        lo = mid;
        std::swap(x_near_, x_mid_);
      }
    }
    if (lo > 0.0) {
      rhs(x_near_, dxdt_near_, t_ + lo);
    } else {
      x_near_ = x_;
      dxdt_near_ = dxdt_;
    }
    // Across the bracket. A stage lies a local error off the trajectory, so the evaluations may
    // see the switch a little before the trajectory reaches it: the step across is lengthened
    // (doubling) until its end is past, up to 1024 brackets (a branch error of ~1e-13 s × F/m);
    // beyond that the step ends there on the near side, and the next, shorter step (its stages
    // closer to the trajectory) locates the switch again.
    double across = hi - lo;
    for (int k = 0; k <= 10; ++k, across *= 2.0) {
      stepper_.stepper().do_step(rhs, x_near_, dxdt_near_, t_ + lo, x_new_, across);
      evaluate_switching(x_new_, t_ + lo + across, g_new_);
      if (sign_changed(g_, g_new_)) return {lo + across, true};
    }
    return {lo + across / 2.0, false};
  }

  /// The order-8 continuous extension of the last accepted step [t_previous_, t_]: RKF7(8)
  /// steps of h/3 and 2h/3 from its start give the interior nodes (continuous_extension.hpp).
  void fit_extension() {
    const double h = t_ - t_previous_;
    SegmentRhs rhs(*form_, scratch_, counters_, t_segment_);
    for (int j = 1; j <= 2; ++j) {
      StateVector& node = j == 1 ? x_node1_ : x_node2_;
      StateVector& rate = j == 1 ? dxdt_node1_ : dxdt_node2_;
      const double t_node = t_previous_ + ContinuousExtension::node_fraction(j) * h;
      stepper_.stepper().do_step(rhs, x_previous_, dxdt_previous_, t_previous_, node,
                                 ContinuousExtension::node_fraction(j) * h);
      rhs(node, rate, t_node);
    }
    // A step that ended at an onset: the derivative at its end is the near side's (the right
    // limit dxdt_ holds the new branch's force, a jump the interpolant must not see).
    const StateVector& end_rate = ended_at_event_ ? dxdt_near_ : dxdt_;
    extension_.fit(
        t_previous_, h, {x_previous_.data(), x_node1_.data(), x_node2_.data(), x_.data()},
        {dxdt_previous_.data(), dxdt_node1_.data(), dxdt_node2_.data(), end_rate.data()});
    extension_fitted_ = true;
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
  /// The works in x as increments since the segment start, and the integrals' tolerances
  /// (reference/integral_weights.hpp; odeint does not restart at events).
  IntegralBase works_{{form_->work_index(), form_->integral_count()}};
  IntegralScaling scaling_;
  ControlledStepper stepper_;
  StateVector x_, x_new_, x_mid_, dxdt_, dxdt_mid_;
  /// The state and derivative at the near end of a located switch's bracket (locate_event).
  StateVector x_near_, dxdt_near_;
  bool ended_at_event_ = false;  ///< the last accepted step ended just past a switch
  SwitchingPredictor predictor_;
  /// The last accepted step's start, and the interior nodes of its continuous extension.
  StateVector x_previous_, dxdt_previous_, x_node1_, dxdt_node1_, x_node2_, dxdt_node2_;
  StateVector x_output_;  ///< the last interpolated output
  ContinuousExtension extension_;
  bool extension_fitted_ = false;
  double t_previous_ = 0.0;
  long steps_since_output_ = 0;
  std::vector<double> g_, g_new_, g_mid_;  ///< switching functions at x_, x_new_, x_mid_
  std::vector<double> g_stage_;            ///< at a watched evaluation (locate_event)
  std::vector<double> carried_;            ///< integrals carried across a segment start
  std::vector<double>* events_ = nullptr;
  double t_ = 0.0;
  double dt_ = 0.0;  ///< proposal for the next step; 0 before the first segment
  double t_segment_ = 0.0;
  /// The joints' rows in force and their last accepted state (core/constraint_tracker.hpp):
  /// moved at segment starts and outputs, read by every evaluation through scratch_.
  core::ConstraintTracker tracker_;
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
