#include "reference/odeint_integrator.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/error.hpp"

namespace flexref::reference::odeint_detail {

Integrator::Integrator(const reference::OdeForm& form, const SolverOptions& options,
                       SolverStats& stats)
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

void Integrator::begin_segment(const core::State& state, double t_segment) {
  t_segment_ = t_segment;
  works_.values(x_.data(), carried_);  // W_d and the extra integrals, across segments
  form_->pack(state, x_.data());
  // Ideal joints: every segment starts on the constraint manifold, where the joints' tracker
  // moves.
  if (form_->model().has_constraints()) {
    form_->project(t_, x_.data(), scratch_);
    form_->unpack(t_, x_.data(), scratch_.state);
    form_->model().advance_tracker(t_, scratch_.state, tracker_, scratch_.workspace);
    counters_.rows_chosen = false;
  }
  works_.start(carried_, x_.data());
  scaling_.factor = 1.0;
  evaluate_derivative();
  evaluate_switching(x_, t_, g_);
  t_previous_ = t_;
  extension_fitted_ = false;
  if (dt_ <= 0.0) dt_ = initial_step(x_, dxdt_, options_.rtol, options_.absolute_tolerance());
}

void Integrator::step(double end) {
  // Whether this step already chose the joints' rows at its start (below).
  bool rows_chosen_at_start = false;
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
    if (counters_.rows_chosen && !rows_chosen_at_start) {
      // A stage chose joint rows of its own (the tracker's fell ill-conditioned within the
      // step): the stages would mix two row sets, and the step's error estimate would not see
      // the change. The tracker chooses the best-conditioned rows at the step's start and the
      // step is taken again on them (once: if its stages still choose, the error test decides).
      const core::Model& model = form_->model();
      form_->unpack(t_, x_.data(), scratch_.state);
      model.advance_tracker(t_, scratch_.state, tracker_, scratch_.workspace,
                            core::TrackerAdvance::kChooseRows);
      counters_.rows_chosen = false;
      rows_chosen_at_start = true;
      evaluate_derivative();
      dt_ = h;
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
          stepper_.stepper().do_step(SegmentRhs(*form_, scratch_, counters_, t_segment_), x_, dxdt_,
                                     t_, x_mid_, h_candidate);
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
    if (counters_.rows_chosen) {
      // Evaluations chose joint rows of their own since the tracker last moved: the tracker
      // chooses them at the accepted state before the next step's first derivative there, so
      // that all of the next step's stages share its rows.
      const core::Model& model = form_->model();
      form_->unpack(t_, x_.data(), scratch_.state);
      model.advance_tracker(t_, scratch_.state, tracker_, scratch_.workspace,
                            core::TrackerAdvance::kChooseRows);
      counters_.rows_chosen = false;
    }
    evaluate_derivative();
    return;
  }
}

void Integrator::output(double t, core::State& state, bool only_output_inside) {
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
  if (model.has_constraints()) {
    model.advance_tracker(t_state, state, tracker_, scratch_.workspace,
                          output_advance(model.joint_multipliers(scratch_.workspace)));
  }
}

void Integrator::output_integrals(double t, std::span<double> out) const {
  if (t >= t_ - time_slack(t_)) {
    works_.values(x_.data(), out);
  } else {
    works_.values(x_output_.data(), out);  // the values output(t) just interpolated
  }
}

void Integrator::normalize() {
  form_->normalize_euler_parameters(x_.data());
  evaluate_derivative();
  evaluate_switching(x_, t_, g_);
}

void Integrator::evaluate_derivative() {
  counters_.nonfinite = false;
  SegmentRhs(*form_, scratch_, counters_, t_segment_)(x_, dxdt_, t_);
  if (counters_.nonfinite) {
    // The derivative at an accepted state does not depend on the step: no step can help.
    throw core::SolverError("odeint", t_, stats_->steps,
                            "the right-hand side is not finite at the current state");
  }
}

void Integrator::evaluate_switching(const StateVector& x, double t, std::vector<double>& g) {
  if (g.empty()) return;
  form_->unpack(t, x.data(), scratch_.state);
  form_->model().switching_functions(core::LoadContext{t, t_segment_}, scratch_.state,
                                     scratch_.workspace, g);
}

bool Integrator::in_contact() const {
  return std::any_of(g_.begin(), g_.end(), [](double g) { return !(g > 0.0); });
}

bool Integrator::halves_agree(double h, double& h_next) {
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
    h_next = std::isfinite(error) ? h * std::max(0.2, 0.9 * std::pow(error, -1.0 / 8.0)) : 0.2 * h;
    return false;
  }
  return true;
}

double Integrator::switching_step_cap(double h) {
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

std::array<double, 2> Integrator::double_crossing_candidates(double h) {
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

std::pair<double, bool> Integrator::locate_event(double h) {
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

void Integrator::fit_extension() {
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
  extension_.fit(t_previous_, h, {x_previous_.data(), x_node1_.data(), x_node2_.data(), x_.data()},
                 {dxdt_previous_.data(), dxdt_node1_.data(), dxdt_node2_.data(), end_rate.data()});
  extension_fitted_ = true;
}

void Integrator::reject(double dt, const char* why) {
  ++stats_->error_test_failures;
  dt_ = dt;
  if (!(dt_ > 4.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t_)))) {
    throw core::SolverError("odeint", t_, stats_->steps, why);
  }
}

}  // namespace flexref::reference::odeint_detail
