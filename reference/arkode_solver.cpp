/// \file arkode_solver.cpp
/// ARKODE's ERKStep with the Fehlberg 13-7-8 table (ARKODE_FEHLBERG_13_7_8: 13 stages, order 8
/// with an embedded order-7 error estimate) on the quasi-velocity ODE form
/// (reference/ode_form.hpp): the third SUNDIALS reference, explicit and of high order, for
/// smooth non-stiff scenes (docs/references.md, "ARKODE").
///
/// - Error control and step-size adaptivity are ARKODE's (its default PID controller, the step
///   adapted after every step: ERKStepSetFixedStepBounds(1, 1), see the constructor).
/// - The segment loop is sundials_segment_driver.hpp: an exact stop (tstop) at every known load
///   discontinuity, root finding (ERKStepRootInit) for contact onset and release with a restart
///   at each.
/// - ARKODE is stepped one step at a time (ARK_ONE_STEP), so that outputs and event states come
///   at the method's order: ARKODE's own dense output is a Hermite polynomial of degree ≤ 5
///   (ARK_INTERP_MAX_DEGREE), below the method's order 8. An output inside a step comes from
///   the order-8 continuous extension of the step (reference/continuous_extension.hpp), the
///   state at a located root from one Fehlberg step of exactly the right length from the step's
///   start; both by a second ERKStep instance with fixed steps. The output grid never shortens
///   the steps: the step sequence is the tolerance's (a tstop at every output would make it the
///   grid's, and the work-precision curve flat).
/// - In contact (a switching function not positive at a step's start) every step is checked
///   against two steps of half its length: the Fehlberg 13-7-8 error estimate compares only the
///   stages at the step's ends (b − b̃ is zero but for stages 1, 11, 12, 13) and accepts a step
///   across a whole stiff contact phase. A step whose halves disagree (ARKODE's WRMS error norm
///   > 1) is discarded and retried from its start with the order-8 controller's smaller step.
/// - No projection (ERKStep has none): |θ| is a first integral of the form, which is
///   homogeneous in θ; θ is renormalized at every restart.
/// - SolverOptions::max_steps bounds the steps between two consecutive output times (ARKODE's
///   mxstep meaning), reported as ARK_TOO_MUCH_WORK.
#include <arkode/arkode.h>
#include <arkode/arkode_erkstep.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "reference/arkode_esdirk_solver.hpp"
#include "reference/continuous_extension.hpp"
#include "reference/method_choice.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_ode_callbacks.hpp"
#include "reference/sundials_segment_driver.hpp"
#include "reference/switching_predictor.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;

/// ARKODE's factor on the step the stability hook returns (its default; it refuses 1).
constexpr double kCflFraction = 0.5;

/// ARKODE's bound on the growth of the step from one step to the next (its default).
constexpr double kMaxGrowth = 20.0;

/// approach_switch: the most error-controlled approaches to one switch, and the shortest
/// distance (in time resolutions, 4 ulp) from the step's start to the switch worth one.
constexpr int kMaxApproaches = 16;
constexpr double kApproachResolutions = 64.0;

/// ERKStep with the Fehlberg 13-7-8 table on the ODE form.
sun::ErkStepMemory make_fehlberg(N_Vector y, SUNContext context, sun::OdeCallbackData& data) {
  sun::ErkStepMemory memory(
      sun::check_created(ERKStepCreate(sun::ode_rhs, 0.0, y, context), "ERKStepCreate"));
  sun::check(ERKStepSetTableNum(memory.get(), ARKODE_FEHLBERG_13_7_8), "ERKStepSetTableNum");
  sun::check(ERKStepSetUserData(memory.get(), &data), "ERKStepSetUserData");
  sun::check(ERKStepSetErrHandlerFn(memory.get(), sun::record_error, &data.log),
             "ERKStepSetErrHandlerFn");
  return memory;
}

/// ARKODE ERKStep on the ODE form, driven segment by segment by integrate_segments.
class ArkodeSegmentSolver final : public sun::SegmentSolver {
 public:
  /// `stabilization`: Baumgarte's rate of the ODE form (ERKStep cannot project).
  ArkodeSegmentSolver(const core::Model& model, const SolverOptions& options, double stabilization)
      : options_(options),
        form_(model, stabilization),
        context_(sun::make_context()),
        y_(make()),
        y_start_(make()),
        y_end_(make()),
        y_node1_(make()),
        y_node2_(make()),
        f_start_(make()),
        f_end_(make()),
        f_node1_(make()),
        f_node2_(make()),
        weights_(make()),
        y_probe_(make()),
        f_probe_(make()),
        y_from_(make()),
        y_near_(make()),
        predictor_(form_),
        g_(static_cast<std::size_t>(model.switching_function_count())),
        g_start_(g_.size()),
        extension_(form_.size()) {
    data_.form = &form_;
    sun::bind_scratch(data_);
    data_.watch_values.assign(g_.size(), 0.0);
    // The integrals' error weights (reference/integral_weights.hpp): the worn depths and the
    // works, contiguous in y; ARKODE's counters survive ERKStepReset, so the steps since the
    // last restart are counted here.
    data_.rtol = options.rtol;
    data_.atol = options.absolute_tolerance();
    data_.integrals = {form_.depth_index(), form_.depth_count() + form_.integral_count()};
    data_.solver_memory = this;
    data_.steps_since_init = [](void* self) {
      const auto* solver = static_cast<const ArkodeSegmentSolver*>(self);
      return solver->accepted_steps_ - solver->restart_steps_;
    };
    erk_ = make_fehlberg(y_.get(), context_.get(), data_);
    if (data_.integrals.count > 0) {
      sun::check(ERKStepWFtolerances(erk_.get(), sun::integral_error_weights<sun::OdeCallbackData>),
                 "ERKStepWFtolerances");
    } else {
      sun::check(ERKStepSStolerances(erk_.get(), options.rtol, options.absolute_tolerance()),
                 "ERKStepSStolerances");
    }
    // Adapt the step after every step: with ARKODE's default hysteresis (keep h while the
    // controller's growth factor is in [1, 1.5]) the error on free_spin stalled at ~1e-11 rad
    // from rtol 1e-10 to 1e-13 with 1.4× the steps; without it the error falls monotonically
    // to 5.5e-13 at rtol 1e-13 (docs/references.md).
    sun::check(ERKStepSetFixedStepBounds(erk_.get(), 1.0, 1.0), "ERKStepSetFixedStepBounds");
    sun::check(ERKStepSetMaxGrowth(erk_.get(), kMaxGrowth), "ERKStepSetMaxGrowth");
    if (!g_.empty()) {
      sun::check(ERKStepRootInit(erk_.get(), model.switching_function_count(), sun::ode_switching),
                 "ERKStepRootInit");
      // The switching cap through ARKODE's explicit-stability hook, h ≤ cfl · h_stab.
      sun::check(ERKStepSetStabilityFn(erk_.get(), switching_cap, this), "ERKStepSetStabilityFn");
      sun::check(ERKStepSetCFLFraction(erk_.get(), kCflFraction), "ERKStepSetCFLFraction");
    }
    // The same method with fixed steps, for the states inside a step.
    restep_ = make_fehlberg(y_.get(), context_.get(), data_);
  }

  void start_segment(const sun::Segment& segment, const core::State& state,
                     std::span<const double> integrals) override {
    data_.t_segment = segment.t_segment;
    form_.pack(state, sun::data(y_.get()));
    // Ideal joints: every segment starts on the constraint manifold (else θ unit), where the
    // joints' tracker moves.
    form_.project(segment.start, sun::data(y_.get()), data_.scratch);
    sun::accept_tracker(data_, segment.start, sun::data(y_.get()));
    works_.start(integrals, sun::data(y_.get()));
    restart(segment.start, segment.end);
  }

  Advance advance(double tout, double next) override {
    long steps_here = 0;
    while (!root_pending_ && t_ < tout - slack(tout)) {
      // One step from (t_, y_); keep its start for the continuous extension and retries.
      N_VScale(1.0, y_.get(), y_start_.get());
      const double t_start = t_;
      const bool in_contact = contact_engaged(t_start, y_start_.get());
      double t_reached = t_start;
      const int flag = ERKStepEvolve(erk_.get(), stop_, y_.get(), &t_reached, ARK_ONE_STEP);
      sun::check(flag, "ERKStepEvolve");
      ++accepted_steps_;
      if (flag == ARK_ROOT_RETURN) {
        // A sign change inside the step just taken, located by ARKODE on its interpolant:
        // locate it on the method's own solution, then reach it by error-controlled steps
        // (approach_switch). It is returned once the outputs before it are written.
        t_ = locate_event(t_start, t_reached);
        if (is_release() && approach_switch(t_start)) continue;
        approaching_ = false;
        root_pending_ = true;
        break;
      }
      if (in_contact && !halves_agree(t_start, t_reached)) {
        // Discard the step and retry from its start with a smaller one.
        --accepted_steps_;
        ++rejected_steps_;
        N_VScale(1.0, y_start_.get(), y_.get());
        sun::check(ERKStepSetInitStep(erk_.get(), retry_step_), "ERKStepSetInitStep");
        sun::check(ERKStepReset(erk_.get(), t_start, y_.get()), "ERKStepReset");
        continue;
      }
      step_start_ = t_start;
      t_ = t_reached;
      fitted_ = false;
      ended_at_event_ = false;
      if (approaching_ && t_ >= approach_end_ - slack(approach_end_)) {
        if (cross_switch()) {
          root_pending_ = true;
          break;
        }
      }
      if (++steps_here > options_.max_steps) {
        data_.log.message = "ARKODE: more than max_steps = " + std::to_string(options_.max_steps) +
                            " steps before reaching tout (too much work)";
        throw sun::SundialsError("ERKStepEvolve", ARK_TOO_MUCH_WORK,
                                 sun::flag_name(ARK_TOO_MUCH_WORK, "ERKStepEvolve"));
      }
    }
    if (root_pending_ && t_ <= tout + slack(tout)) {
      root_pending_ = false;
      output_ready_ = false;  // y_ is the state at the event
      return {t_, true};
    }
    output_at(tout, next);
    return {tout, false};
  }

  void restart_at_root(double t, const sun::Segment& segment) override {
    form_.project(t, sun::data(y_.get()), data_.scratch);
    sun::accept_tracker(data_, t, sun::data(y_.get()));
    works_.rebase(sun::data(y_.get()));
    restart(t, segment.end);
  }

  void unpack(double t, core::State& state) const override {
    form_.unpack(t, sun::data(output_ready_ ? y_end_.get() : y_.get()), state);
  }
  void accept_output(double t, const core::State& state) override {
    sun::accept_tracker(data_, t, state);
  }
  void integrals(std::span<double> out) const override {
    works_.values(sun::data(output_ready_ ? y_end_.get() : y_.get()), out);
  }

  void add_counters(SolverStats& stats) const override {
    long error_fails = 0;
    sun::check(ERKStepGetNumErrTestFails(erk_.get(), &error_fails), "ERKStepGetNumErrTestFails");
    // ARKODE's counters survive ERKStepReset: add what accrued since the last call.
    stats.steps += accepted_steps_ - counted_.steps;
    stats.error_test_failures += error_fails + rejected_steps_ - counted_.error_test_failures;
    stats.rhs_evaluations += data_.evaluations - counted_.rhs_evaluations;
    counted_.steps = accepted_steps_;
    counted_.error_test_failures = error_fails + rejected_steps_;
    counted_.rhs_evaluations = data_.evaluations;
  }

  double current_time(double fallback) const override { return std::isnan(t_) ? fallback : t_; }
  long current_steps() const override { return accepted_steps_ - counted_.steps; }
  std::string failure_message(const std::string& what) const override {
    return sun::failure_message(what, data_, "right-hand side");
  }

 private:
  sun::Vector make() { return sun::make_vector(form_.size(), context_.get()); }

  /// ARKExpStabFn: SwitchingPredictor's cap on a step from (t, y) over the longest step ARKODE
  /// may try next, kMaxGrowth times its current one (0: no cap). ARKODE calls it before every
  /// step attempt.
  static int switching_cap(N_Vector y, sunrealtype t, sunrealtype* h_stab, void* user_data) {
    auto& self = *static_cast<ArkodeSegmentSolver*>(user_data);
    *h_stab = 0.0;
    try {
      double h = 0.0;
      if (ERKStepGetCurrentStep(self.erk_.get(), &h) < 0 || !(h > 0.0)) return 0;
      h *= kMaxGrowth;
      sun::OdeCallbackData& d = self.data_;
      if (sun::ode_rhs(t, y, self.f_probe_.get(), &d) != 0) return 0;
      if (sun::ode_switching(t, y, self.g_.data(), &d) != 0) return -1;
      const double cap = self.predictor_.cap(
          t, sun::data(y), sun::data(self.f_probe_.get()), self.g_, h, d.t_segment,
          [&self, &d](double tau, const double* x, double* xdot) {
            N_Vector probe = self.y_probe_.get();
            std::copy(x, x + self.form_.size(), sun::data(probe));
            return sun::ode_rhs(tau, probe, self.f_end_.get(), &d) == 0 &&
                   (std::copy(sun::data(self.f_end_.get()),
                              sun::data(self.f_end_.get()) + self.form_.size(), xdot),
                    true);
          },
          d.scratch);
      if (cap < h) *h_stab = cap / kCflFraction;
    } catch (...) {
      self.data_.callback_error = std::current_exception();
      return -1;
    }
    return 0;
  }

  static double slack(double t) {
    return 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
  }

  /// A new step sequence from y_ at t0 up to the stop time `stop`.
  void restart(double t0, double stop) {
    sun::check(ERKStepSetInitStep(erk_.get(), 0.0), "ERKStepSetInitStep");  // ARKODE's estimate
    sun::check(ERKStepReset(erk_.get(), t0, y_.get()), "ERKStepReset");
    sun::check(ERKStepSetStopTime(erk_.get(), stop), "ERKStepSetStopTime");
    restart_steps_ = accepted_steps_;
    t_ = t0;
    step_start_ = t0;
    stop_ = stop;
    fitted_ = false;
    ended_at_event_ = false;
    output_ready_ = false;
    root_pending_ = false;
    approaching_ = false;
    approaches_ = 0;
  }

  /// Some switching function is not positive at (t, y), a step's start; keeps them in g_start_.
  bool contact_engaged(double t, N_Vector y) {
    if (g_start_.empty()) return false;
    sun::check(sun::ode_switching(t, y, g_start_.data(), &data_), "ERKStepRootFn");
    return std::any_of(g_start_.begin(), g_start_.end(), [](double g) { return !(g > 0.0); });
  }

  /// After locate_event found a switch inside the step from (t0, y_start_): that step was
  /// accepted on an error estimate over both branches, and the state at the switch came from one
  /// unchecked Fehlberg step onto the non-smooth end of the branch (a Hunt–Crossley force
  /// ∝ δ^1.5 leaves the solution only C³ at a release: that step's error is ~h^3.5, not the
  /// method's h⁹). Measured on bouncing_ball (1 s, 2 impacts) with that step kept: an energy
  /// balance of 1.2e-5, 2.8e-6, 2.5e-7 J at rtol 1e-8, 1e-10, 1e-12, i.e. ~6× per 100×. So the step
  /// is discarded and the integration restarts from t0 under ARKODE's error control, with a stop
  /// (tstop) at the switch's near side, where cross_switch takes
  /// the short located step across; no accepted step then straddles the switch (as in
  /// precision/switched_integration.hpp). An approach whose own step meets the switch early is
  /// approached again from that step's start, so each retry starts closer; at most
  /// kMaxApproaches per switch, after which the located step is kept as before. Returns whether
  /// an approach started.
  bool approach_switch(double t0) {
    const double near = near_time_;
    const double resolution =
        4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t0));
    if (approaches_ >= kMaxApproaches || !(near - t0 > kApproachResolutions * resolution)) {
      approaches_ = 0;
      return false;
    }
    ++approaches_;
    event_time_ = t_;
    N_VScale(1.0, y_start_.get(), y_.get());
    // ARKODE's own first step, so that the switching cap bounds the steps towards the switch
    // (a forced first step of half the way skips it: on hinged_spinner_strike at rtol 1e-11
    // one such step before a damped onset was off by 2e-7 m/s).
    sun::check(ERKStepSetInitStep(erk_.get(), 0.0), "ERKStepSetInitStep");
    sun::check(ERKStepReset(erk_.get(), t0, y_.get()), "ERKStepReset");
    sun::check(ERKStepSetStopTime(erk_.get(), near), "ERKStepSetStopTime");
    t_ = t0;
    approach_end_ = near;
    approaching_ = true;
    return true;
  }

  /// The approach reached the near side of the switch (y_ at approach_end_): the short step
  /// across it, lengthened (doubling) until its end is on the new side. Leaves y_ past the switch,
  /// the near side in y_near_, and returns true; false when no such step reaches the switch (the
  /// trajectory meets it later): the integration then goes on from the near side towards the
  /// segment end, and ARKODE's root finding sees the switch again.
  bool cross_switch() {
    approaching_ = false;
    N_VScale(1.0, y_.get(), y_near_.get());
    const double lo = approach_end_;
    const double resolution =
        4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(lo));
    double across = std::max(event_time_ - lo, 8.0 * resolution);
    for (int k = 0; k <= 10; ++k, across *= 2.0) {
      fixed_step(lo, y_near_.get(), across, y_.get());
      form_.normalize_euler_parameters(sun::data(y_.get()));
      if (switch_changed(lo + across, y_.get())) {
        t_ = lo + across;
        fitted_ = false;
        ended_at_event_ = true;
        near_time_ = lo;
        approaches_ = 0;
        return true;
      }
    }
    N_VScale(1.0, y_near_.get(), y_.get());
    t_ = lo;
    sun::check(ERKStepSetInitStep(erk_.get(), 0.0), "ERKStepSetInitStep");
    sun::check(ERKStepReset(erk_.get(), lo, y_.get()), "ERKStepReset");
    sun::check(ERKStepSetStopTime(erk_.get(), stop_), "ERKStepSetStopTime");
    return false;
  }

  /// The switch locate_event just found is a release: a function not positive at the step's
  /// start (g_start_) is positive past the switch (g_, its values at y_). An onset is not
  /// approached: its state comes from the located step as before (an onset's force, ∝ δⁿ from
  /// zero or c δ̇ for the damped linear law, is on the far side of the step's end, where the
  /// approach found nothing to gain on bouncing_ball and tube_support_impact and, for the damped
  /// linear law's jump, lost accuracy on hinged_spinner_strike: 4e-4 m at rtol 1e-8).
  bool is_release() const {
    for (std::size_t k = 0; k < g_.size(); ++k) {
      if (!(g_start_[k] > 0.0) && g_[k] > 0.0) return true;
    }
    return false;
  }

  /// Some switching function at (t, y) is on another side than at the last step's start
  /// (g_start_).
  bool switch_changed(double t, N_Vector y) {
    sun::check(sun::ode_switching(t, y, g_.data(), &data_), "ERKStepRootFn");
    for (std::size_t k = 0; k < g_.size(); ++k) {
      if ((g_start_[k] > 0.0) != (g_[k] > 0.0)) return true;
    }
    return false;
  }

  /// The event time, to a few ulp, inside the step from (t0, y_start_) whose switching
  /// functions changed side: bisection on the length of one Fehlberg step from its start (the
  /// step's own solution, as accurate as the step), from ARKODE's bracket (its estimate t_root,
  /// from its degree-5 interpolant, placed roots up to 2e-5 s off on bouncing_ball) and the
  /// step's end. A trial counts as past the switch when its end or any of its stages is on
  /// another side than the start (a stage near the end lies a local error off the trajectory,
  /// and a damped penalty law jumps at an onset, F = c δ̇ at δ = 0: one stage there added
  /// ~b_i h c δ̇ / m to the step, 6e-5 m on hinged_spinner_strike at every tolerance). The state
  /// past the switch is one clean step to the bracket's near end, then one across it, lengthened
  /// (doubling, up to 1024 brackets) until its end is past; when it is not, the bisection starts
  /// again from that near end with short, accurate trials. Leaves y_ just past the zero, on the
  /// new side, and the near side's state in y_near_ (the continuous extension's left limit), and
  /// returns its time.
  double locate_event(double t0, double t_root) {
    // g at the start: contact_engaged(t0, y_start_) filled g_start_ before the step.
    double t_end = t0;
    sun::check(ERKStepGetCurrentTime(erk_.get(), &t_end), "ERKStepGetCurrentTime");
    double t_a = t0;  // the trials' start: the step's, or a near end the step across missed
    N_VScale(1.0, y_start_.get(), y_from_.get());
    const auto end_changed = [&](double t, N_Vector y) {
      sun::check(sun::ode_switching(t, y, g_.data(), &data_), "ERKStepRootFn");
      for (std::size_t k = 0; k < g_.size(); ++k) {
        if ((g_start_[k] > 0.0) != (g_[k] > 0.0)) return true;
      }
      return false;
    };
    const auto changed_at = [&](double t, N_Vector out) {
      data_.watch_start = &g_start_;
      data_.other_side = false;
      fixed_step(t_a, y_from_.get(), t - t_a, out);
      data_.watch_start = nullptr;
      const bool stages = data_.other_side;
      return end_changed(t, out) || stages;
    };
    double lo = t0;
    double hi = t_end;
    if (t_root > t0 && t_root < t_end) {
      if (changed_at(t_root, y_end_.get())) {
        hi = t_root;
      } else {
        lo = t_root;
      }
    }
    const double resolution =
        4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t0));
    for (int round = 0; round < 16; ++round) {
      bool near_found = lo > t_a;
      if (near_found) fixed_step(t_a, y_from_.get(), lo - t_a, y_near_.get());
      for (int k = 0; k < 200 && hi - lo > resolution; ++k) {
        const double mid = 0.5 * (lo + hi);
        if (changed_at(mid, y_end_.get())) {
          hi = mid;
        } else {
          lo = mid;
          N_VScale(1.0, y_end_.get(), y_near_.get());
          near_found = true;
        }
      }
      if (!near_found) N_VScale(1.0, y_from_.get(), y_near_.get());
      // At least 8 resolutions across, and θ renormalized as restart_at_root will: the end must
      // stay past the switch after that projection (a margin of ~ġ × 2e-15 s against its ~1e-16
      // relative change of the points; the branch error of so short a step is ~1e-14 m/s).
      double across = std::max(hi - lo, 8.0 * resolution);
      for (int k = 0; k <= 10; ++k, across *= 2.0) {
        fixed_step(lo, y_near_.get(), across, y_.get());
        form_.normalize_euler_parameters(sun::data(y_.get()));
        if (end_changed(lo + across, y_.get())) {
          step_start_ = t0;
          fitted_ = false;
          ended_at_event_ = true;
          near_time_ = lo;
          return lo + across;
        }
      }
      // The trajectory reaches the switch later than the stages saw it: bisect again from the
      // near end (the original step's end is past it).
      t_a = lo;
      N_VScale(1.0, y_near_.get(), y_from_.get());
      hi = t_end;
    }
    throw sun::SundialsError("ERKStepRootFn", ARK_RTFUNC_FAIL,
                             "the switch could not be located on the method's own solution");
  }

  /// The step-doubling test of the step (t0, y_start_) → (t1, y_): two Fehlberg steps of half
  /// its length agree with it in ARKODE's WRMS error norm. On failure retry_step_ is the
  /// order-8 controller's proposal, h (0.9 / error)^(1/8) within [h/5, h/2].
  bool halves_agree(double t0, double t1) {
    const double h = t1 - t0;
    fixed_step(t0, y_start_.get(), 0.5 * h, y_node1_.get());
    fixed_step(t0 + 0.5 * h, y_node1_.get(), 0.5 * h, y_node2_.get());
    sun::check(ERKStepGetErrWeights(erk_.get(), weights_.get()), "ERKStepGetErrWeights");
    N_VLinearSum(1.0, y_node2_.get(), -1.0, y_.get(), y_node1_.get());
    const double error = N_VWrmsNorm(y_node1_.get(), weights_.get());
    if (error <= 1.0) return true;
    retry_step_ = std::isfinite(error) ? h * std::clamp(0.9 * std::pow(error, -1.0 / 8.0), 0.2, 0.5)
                                       : 0.2 * h;
    return false;
  }

  /// y_end_ = the state at tout inside or at the end of the last step [step_start_, t_]: the
  /// step's own end value there; inside, when tout is the step's only output (the next request
  /// lies beyond the step's end), one Fehlberg step from the step's start onto it, else its
  /// continuous extension (fitted once per step). Both are of the method's order.
  void output_at(double tout, double next) {
    output_ready_ = true;
    if (tout >= t_ - slack(t_) || !(t_ > step_start_)) {
      N_VScale(1.0, y_.get(), y_end_.get());
      return;
    }
    if (!fitted_ && next >= t_ - slack(t_)) {
      fixed_step(step_start_, y_start_.get(), tout - step_start_, y_end_.get());
      return;
    }
    if (!fitted_) fit_extension();
    extension_.evaluate(tout, sun::data(y_end_.get()));
  }

  /// The order-8 continuous extension of [step_start_, t_]: the ends, two interior nodes by
  /// fixed steps of h/3 and 2h/3 from the start, and the derivative at each node.
  void fit_extension() {
    const double h = t_ - step_start_;
    fixed_step(step_start_, y_start_.get(), ContinuousExtension::node_fraction(1) * h,
               y_node1_.get());
    fixed_step(step_start_, y_start_.get(), ContinuousExtension::node_fraction(2) * h,
               y_node2_.get());
    // A step that ended at an onset: the derivative at its end is the near side's (the left
    // limit; at y_ the new branch's force jumps).
    const std::array<N_Vector, 4> nodes{y_start_.get(), y_node1_.get(), y_node2_.get(),
                                        ended_at_event_ ? y_near_.get() : y_.get()};
    const std::array<N_Vector, 4> rates{f_start_.get(), f_node1_.get(), f_node2_.get(),
                                        f_end_.get()};
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      const double t_node =
          step_start_ + ContinuousExtension::node_fraction(static_cast<int>(j)) * h;
      const double t_rate = j == 3 && ended_at_event_ ? near_time_ : t_node;
      if (sun::ode_rhs(t_rate, nodes[j], rates[j], &data_) != 0) {
        throw sun::SundialsError("ERKStepRhs", ARK_RHSFUNC_FAIL,
                                 sun::flag_name(ARK_RHSFUNC_FAIL, "ERKStepEvolve"));
      }
    }
    extension_.fit(step_start_, h,
                   {sun::data(y_start_.get()), sun::data(y_node1_.get()), sun::data(y_node2_.get()),
                    sun::data(y_.get())},
                   {sun::data(f_start_.get()), sun::data(f_node1_.get()), sun::data(f_node2_.get()),
                    sun::data(f_end_.get())});
    fitted_ = true;
  }

  /// out = one Fehlberg 13-7-8 step of length h from (t0, y0) (out may not alias y0).
  void fixed_step(double t0, N_Vector y0, double h, N_Vector out) {
    sun::check(ERKStepSetFixedStep(restep_.get(), h), "ERKStepSetFixedStep");
    sun::check(ERKStepReset(restep_.get(), t0, y0), "ERKStepReset");
    double t_reached = t0;
    sun::check(ERKStepEvolve(restep_.get(), t0 + h, out, &t_reached, ARK_ONE_STEP),
               "ERKStepEvolve");
  }

  SolverOptions options_;
  OdeForm form_;
  /// The works in y as increments since the last (re)start (reference/integral_weights.hpp).
  IntegralBase works_{{form_.work_index(), form_.integral_count()}};
  sun::OdeCallbackData data_;
  sun::Context context_;
  sun::Vector y_;                                    ///< the solution at t_
  sun::Vector y_start_, y_end_, y_node1_, y_node2_;  ///< step start, output, interior nodes
  sun::Vector f_start_, f_end_, f_node1_, f_node2_;
  sun::Vector weights_;
  sun::Vector y_probe_, f_probe_;  ///< the switching cap's evaluations
  /// locate_event: the trials' start, and the near end of the located bracket.
  sun::Vector y_from_, y_near_;
  /// approach_switch: the located time past the switch, the near side's time the approach stops
  /// at, and how many approaches this switch has had.
  double event_time_ = 0.0;
  double approach_end_ = 0.0;
  bool approaching_ = false;
  int approaches_ = 0;
  bool ended_at_event_ = false;  ///< the last accepted step ended just past a switch
  double near_time_ = 0.0;       ///< the time of y_near_
  SwitchingPredictor predictor_;
  /// Switching functions: scratch (locate_event, switching_cap) and at a step's start.
  std::vector<double> g_, g_start_;
  ContinuousExtension extension_;
  double t_ = 0.0;           ///< time of y_
  double step_start_ = 0.0;  ///< start of the last accepted step
  double stop_ = 0.0;        ///< the segment's end (tstop)
  double retry_step_ = 0.0;
  bool fitted_ = false;        ///< extension_ fits [step_start_, t_]
  bool output_ready_ = false;  ///< y_end_ holds the last output (else y_ is the state)
  bool root_pending_ = false;  ///< y_, t_ are a located event not yet returned
  long accepted_steps_ = 0;
  long restart_steps_ = 0;       ///< accepted_steps_ at the last restart
  long rejected_steps_ = 0;      ///< steps discarded by the contact step-doubling test
  mutable SolverStats counted_;  ///< counters already added to the run
  // Declared last so that they are freed first (as in SUNDIALS' examples).
  sun::ErkStepMemory erk_;
  sun::ErkStepMemory restep_;
};

}  // namespace

ReferenceRun solve_arkode(const core::Model& model, const std::vector<double>& output_times,
                          const SolverOptions& options) {
  ArkodeMethodChoice choice{options.arkode_method, "chosen with --method"};
  if (options.arkode_method == ArkodeMethod::kAuto) {
    choice = choose_arkode_method(model, mean_output_spacing(output_times));
  }
  if (choice.method == ArkodeMethod::kEsdirk) {
    ReferenceRun run = solve_arkode_esdirk(model, output_times, options);
    run.method_reason = choice.reason;
    return run;
  }
  // ERKStep has no projection: the joints' drift is damped instead (Baumgarte).
  const double stabilization =
      constraint_stabilization_rate(model, mean_output_spacing(output_times));
  ReferenceRun run = sun::integrate_segments(model, output_times, options, "arkode", [&] {
    return std::make_unique<ArkodeSegmentSolver>(model, options, stabilization);
  });
  run.method = "erk-fehlberg-13-7-8";
  run.method_reason = choice.reason;
  return run;
}

}  // namespace flexref::reference
