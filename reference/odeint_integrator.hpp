#pragma once
/// \file odeint_integrator.hpp
/// The stepping of Odeint's reference on one segment (reference/odeint_solver.cpp has the
/// method and its choices): Boost.Odeint's controlled RKF7(8) on the ODE form with the integral
/// components' own tolerances, steps landing on the segment end and ending just past a located
/// switch, the step-doubling test in contact, and the order-8 dense output. Internal to
/// reference/ (included by odeint_solver.cpp and odeint_integrator.cpp).
#include <array>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "reference/continuous_extension.hpp"
#include "reference/integral_weights.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/switching_predictor.hpp"

namespace flexref::reference::odeint_detail {

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
inline double time_slack(double t) {
  return 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
}

inline bool all_finite(const StateVector& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

/// Some switching function changed side (positive ↔ not positive).
inline bool sign_changed(const std::vector<double>& a, const std::vector<double>& b) {
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
  /// Set when an evaluation chose joint rows of its own (its tracker's were ill-conditioned at
  /// its state: core::JointMultipliers::rows_chosen); cleared where the tracker moves.
  bool rows_chosen = false;
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
    const core::Model& model = form_->model();
    if (model.has_constraints() && model.joint_multipliers(scratch_->workspace).rows_chosen()) {
      counters_->rows_chosen = true;
    }
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
inline double initial_step(const StateVector& x, const StateVector& dxdt, double rtol,
                           double atol) {
  double d0 = 0.0, d1 = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double scale = atol + rtol * std::abs(x[i]);
    d0 += (x[i] / scale) * (x[i] / scale);
    d1 += (dxdt[i] / scale) * (dxdt[i] / scale);
  }
  if (d0 < 1e-10 || d1 < 1e-10) return 1e-6;
  return 0.01 * std::sqrt(d0 / d1);
}

/// RKF7(8) on one segment at a time: begin_segment, then step(end) until time() == end, with
/// the outputs inside each step taken by output().
class Integrator {
 public:
  Integrator(const reference::OdeForm& form, const SolverOptions& options, SolverStats& stats);

  /// Where located event times are appended.
  void record_events_in(std::vector<double>* events) { events_ = events; }

  double time() const { return t_; }

  /// Starts a segment at the current time: the loads switch to the branch at t_segment.
  void begin_segment(const core::State& state, double t_segment);

  /// One accepted step from the current time, truncated to land exactly on `end` (the segment
  /// end) and ended just past a located event. Keeps the step's start for output().
  void step(double end);

  /// The state at an output time t in [start of the last step, time()]: the step's end value
  /// at its end; inside, when it is the step's only output, an RKF7(8) step of length
  /// t − start from the step's start (12 evaluations), else the continuous extension (fitted
  /// once per step, 26 evaluations). Both are of the method's order; the first halves the cost
  /// of dense-output scenes whose steps hold about one output each (flexible_spinner at rtol
  /// 1e-12: 1022 steps for 1000 outputs). The output is a state of the integration: the joints'
  /// tracker moves there.
  void output(double t, core::State& state, bool only_output_inside);
  /// W_d and the extra integrals at the output t just computed by output().
  void output_integrals(double t, std::span<double> out) const;

  /// Projects θ onto the unit sphere (at segment ends).
  void normalize();

  void unpack(core::State& state) const { form_->unpack(time(), x_.data(), state); }
  long rhs_evaluations() const { return counters_.rhs_evaluations; }

 private:
  void evaluate_derivative();

  void evaluate_switching(const StateVector& x, double t, std::vector<double>& g);

  /// Some switching function is not positive at the step's start: a contact is engaged.
  bool in_contact() const;

  /// The step-doubling test of a step taken in contact (x_new_ after h from x_): RKF7(8)'s own
  /// error estimate, 41/840 (k1 + k11 − k12 − k13) h, compares only the stages at the step's ends
  /// and accepts a step across a whole stiff contact phase (measured on bouncing_ball: a 0.011 s
  /// step from an impact's onset through its compression, in error by millimetres, passed it).
  /// Two steps of h/2 must agree with the step in odeint's own error norm,
  /// max_i |Δ_i| / (atol + rtol (|x_i| + h |ẋ_i|)) ≤ 1; the difference estimates the step's
  /// local error (1 − 2⁻⁸ of it). On failure h_next is the order-8 controller's proposal.
  bool halves_agree(double h, double& h_next);

  /// SwitchingPredictor's cap on a step of length h from the current state.
  double switching_step_cap(double h);

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
  std::array<double, 2> double_crossing_candidates(double h);

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
  std::pair<double, bool> locate_event(double h);

  /// The order-8 continuous extension of the last accepted step [t_previous_, t_]: RKF7(8)
  /// steps of h/3 and 2h/3 from its start give the interior nodes (continuous_extension.hpp).
  void fit_extension();

  void reject(double dt, const char* why);

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

}  // namespace flexref::reference::odeint_detail
