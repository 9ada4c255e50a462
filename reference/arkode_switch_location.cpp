/// \file arkode_switch_location.cpp
/// ARKODE's reference at the switches of contact laws (reference/arkode_solver.cpp): the cap
/// on a step towards a switch (SwitchingPredictor through ARKODE's stability hook), the
/// step-doubling test in contact, the location of a switch inside a step on the method's own
/// solution, and the error-controlled approach to a release and the short step across it.
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "reference/arkode_segment_solver.hpp"

namespace flexref::reference::arkode_detail {

int ArkodeSegmentSolver::switching_cap(N_Vector y, sunrealtype t, sunrealtype* h_stab,
                                       void* user_data) {
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

bool ArkodeSegmentSolver::contact_engaged(double t, N_Vector y) {
  if (g_start_.empty()) return false;
  sun::check(sun::ode_switching(t, y, g_start_.data(), &data_), "ERKStepRootFn");
  return std::any_of(g_start_.begin(), g_start_.end(), [](double g) { return !(g > 0.0); });
}

bool ArkodeSegmentSolver::approach_switch(double t0) {
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

bool ArkodeSegmentSolver::cross_switch() {
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

bool ArkodeSegmentSolver::is_release() const {
  for (std::size_t k = 0; k < g_.size(); ++k) {
    if (!(g_start_[k] > 0.0) && g_[k] > 0.0) return true;
  }
  return false;
}

bool ArkodeSegmentSolver::switch_changed(double t, N_Vector y) {
  sun::check(sun::ode_switching(t, y, g_.data(), &data_), "ERKStepRootFn");
  for (std::size_t k = 0; k < g_.size(); ++k) {
    if ((g_start_[k] > 0.0) != (g_[k] > 0.0)) return true;
  }
  return false;
}

double ArkodeSegmentSolver::locate_event(double t0, double t_root) {
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

bool ArkodeSegmentSolver::halves_agree(double t0, double t1) {
  const double h = t1 - t0;
  fixed_step(t0, y_start_.get(), 0.5 * h, y_node1_.get());
  fixed_step(t0 + 0.5 * h, y_node1_.get(), 0.5 * h, y_node2_.get());
  sun::check(ERKStepGetErrWeights(erk_.get(), weights_.get()), "ERKStepGetErrWeights");
  N_VLinearSum(1.0, y_node2_.get(), -1.0, y_.get(), y_node1_.get());
  const double error = N_VWrmsNorm(y_node1_.get(), weights_.get());
  if (error <= 1.0) return true;
  retry_step_ =
      std::isfinite(error) ? h * std::clamp(0.9 * std::pow(error, -1.0 / 8.0), 0.2, 0.5) : 0.2 * h;
  return false;
}

}  // namespace flexref::reference::arkode_detail
