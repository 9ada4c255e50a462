#include "reference/arkode_segment_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace flexref::reference::arkode_detail {

sun::ErkStepMemory make_fehlberg(N_Vector y, SUNContext context, sun::OdeCallbackData& data) {
  sun::ErkStepMemory memory(
      sun::check_created(ERKStepCreate(sun::ode_rhs, 0.0, y, context), "ERKStepCreate"));
  sun::check(ERKStepSetTableNum(memory.get(), ARKODE_FEHLBERG_13_7_8), "ERKStepSetTableNum");
  sun::check(ERKStepSetUserData(memory.get(), &data), "ERKStepSetUserData");
  sun::check(ERKStepSetErrHandlerFn(memory.get(), sun::record_error, &data.log),
             "ERKStepSetErrHandlerFn");
  return memory;
}

ArkodeSegmentSolver::ArkodeSegmentSolver(const core::Model& model, const SolverOptions& options,
                                         double stabilization)
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

void ArkodeSegmentSolver::start_segment(const sun::Segment& segment, const core::State& state,
                                        std::span<const double> integrals) {
  data_.t_segment = segment.t_segment;
  form_.pack(state, sun::data(y_.get()));
  // Ideal joints: every segment starts on the constraint manifold (else θ unit), where the
  // joints' tracker moves.
  form_.project(segment.start, sun::data(y_.get()), data_.scratch);
  sun::accept_tracker(data_, segment.start, sun::data(y_.get()));
  works_.start(integrals, sun::data(y_.get()));
  restart(segment.start, segment.end);
}

ArkodeSegmentSolver::Advance ArkodeSegmentSolver::advance(double tout, double next) {
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
    sun::accept_step(data_, t_reached, sun::data(y_.get()));
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

void ArkodeSegmentSolver::restart_at_root(double t, const sun::Segment& segment) {
  form_.project(t, sun::data(y_.get()), data_.scratch);
  sun::accept_tracker(data_, t, sun::data(y_.get()));
  works_.rebase(sun::data(y_.get()));
  restart(t, segment.end);
}

void ArkodeSegmentSolver::unpack(double t, core::State& state) const {
  form_.unpack(t, sun::data(output_ready_ ? y_end_.get() : y_.get()), state);
}

void ArkodeSegmentSolver::accept_output(double t, const core::State& state) {
  sun::accept_output(data_, t, state);
}

void ArkodeSegmentSolver::integrals(std::span<double> out) const {
  works_.values(sun::data(output_ready_ ? y_end_.get() : y_.get()), out);
}

void ArkodeSegmentSolver::add_counters(SolverStats& stats) const {
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

std::string ArkodeSegmentSolver::failure_message(const std::string& what) const {
  return sun::failure_message(what, data_, "right-hand side");
}

double ArkodeSegmentSolver::slack(double t) {
  return 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
}

void ArkodeSegmentSolver::restart(double t0, double stop) {
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

void ArkodeSegmentSolver::output_at(double tout, double next) {
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

void ArkodeSegmentSolver::fit_extension() {
  const double h = t_ - step_start_;
  fixed_step(step_start_, y_start_.get(), ContinuousExtension::node_fraction(1) * h,
             y_node1_.get());
  fixed_step(step_start_, y_start_.get(), ContinuousExtension::node_fraction(2) * h,
             y_node2_.get());
  // A step that ended at an onset: the derivative at its end is the near side's (the left
  // limit; at y_ the new branch's force jumps).
  const std::array<N_Vector, 4> nodes{y_start_.get(), y_node1_.get(), y_node2_.get(),
                                      ended_at_event_ ? y_near_.get() : y_.get()};
  const std::array<N_Vector, 4> rates{f_start_.get(), f_node1_.get(), f_node2_.get(), f_end_.get()};
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    const double t_node = step_start_ + ContinuousExtension::node_fraction(static_cast<int>(j)) * h;
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

void ArkodeSegmentSolver::fixed_step(double t0, N_Vector y0, double h, N_Vector out) {
  sun::check(ERKStepSetFixedStep(restep_.get(), h), "ERKStepSetFixedStep");
  sun::check(ERKStepReset(restep_.get(), t0, y0), "ERKStepReset");
  double t_reached = t0;
  sun::check(ERKStepEvolve(restep_.get(), t0 + h, out, &t_reached, ARK_ONE_STEP), "ERKStepEvolve");
}

}  // namespace flexref::reference::arkode_detail
