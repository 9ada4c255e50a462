#pragma once
/// \file switched_integration.hpp
/// Integration across the switches of a model (contact onsets and releases, the clamp of a
/// penalty law) in any precision, with Boost.Odeint's Bulirsch–Stoer: docs/precision.md,
/// "Events". Internal to precision/ (included by high_precision_reference.cpp only).
///
/// Extrapolation assumes a smooth solution across a step; a contact force is only continuous
/// at its onset (F ∝ δⁿ) and its derivative jumps at a release or a clamp. So no step may
/// straddle a switch: every accepted step whose end has another switching pattern than its start
/// is cut back to the first sign change, located by the Illinois variant of regula falsi on
/// τ ↦ g_j(y(τ)), where y(τ) is integrated afresh from the step's start (a smooth problem:
/// the step's start and τ ≤ the root lie on one side). The bracket is shrunk to four ulps of
/// the time, so an event is located to the working precision (3e-34 s near t = 1 s in quad),
/// and the integration restarts on the far side of it (the state there has the new pattern).
/// A step whose ends agree but whose evaluations saw another contact pattern (a graze inside
/// the step) is halved and retried.
#include <algorithm>
#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace flexref::precision::detail {

/// One located switch.
template <typename S>
struct SwitchEvent {
  S t;
  int function = 0;          ///< index of the switching function that changed sign
  bool to_negative = false;  ///< the function went from ≥ 0 to < 0
};

/// Counters of a switched integration.
struct SwitchedCounters {
  long steps = 0;
  long evaluations = 0;
  long events = 0;
  long located_evaluations = 0;  ///< evaluations spent in locating events
};

/// Whether function j's sign change between values a and b is an event. Even functions are
/// gaps (a pair pushes while g < 0), odd ones the clamp of the same pair, which matters only
/// while the pair is inside at both values.
template <typename S>
bool changed(const std::vector<S>& a, const std::vector<S>& b, std::size_t j) {
  if ((a[j] < S(0)) == (b[j] < S(0))) return false;
  if (j % 2 == 0) return true;
  return a[j - 1] < S(0) && b[j - 1] < S(0);
}

/// Integrates `y` from t = a through every stop time (sorted, in (a, b], the last = b),
/// calling on_stop(index, y) there and on_event(event, y) at every located switch. `model`
/// has derivative(y, dydt, t, t_segment, switching*) (filling the switching values when given),
/// switching_function_count() and switching_functions(t, y, values). Throws core::SolverError when
/// Bulirsch–Stoer cannot reach the tolerance or an event cannot be bracketed.
template <typename S, typename Model, typename OnStop, typename OnEvent>
void integrate_switched(const Model& model, std::vector<S>& y, double a,
                        const std::vector<S>& stops, double t_segment, S tol, S first_step,
                        const std::string& solver_name, SwitchedCounters& counters, OnStop on_stop,
                        OnEvent on_event) {
  namespace odeint = boost::numeric::odeint;
  using State = std::vector<S>;
  using std::abs;
  const auto m = static_cast<std::size_t>(model.switching_function_count());
  const S eps = std::numeric_limits<S>::epsilon();
  std::vector<S> g0(m), g1(m), gm(m);
  model.switching_functions(S(a), y, g0);

  bool graze = false;
  std::vector<S> g_eval(m);
  const auto system = [&](const State& x, State& dxdt, const S t) {
    ++counters.evaluations;
    model.derivative(x, dxdt, t, t_segment, &g_eval);  // the switching values come along
    for (std::size_t j = 0; j < m; j += 2) graze = graze || ((g_eval[j] < S(0)) != (g0[j] < S(0)));
  };
  const auto smooth_system = [&](const State& x, State& dxdt, const S t) {
    ++counters.located_evaluations;
    model.derivative(x, dxdt, t, t_segment);
  };
  // y(τ) integrated afresh from (t0, y0): the same tolerance, a new step sequence.
  const auto state_at = [&](const State& y0, S t0, S tau) {
    State x = y0;
    if (tau > t0) {
      odeint::bulirsch_stoer<State, S> fresh(tol, tol);
      odeint::integrate_adaptive(fresh, smooth_system, x, t0, tau, S(tau - t0));
    }
    return x;
  };

  odeint::bulirsch_stoer<State, S> stepper(tol, tol);
  S t(a);
  S dt = first_step;
  std::size_t next = 0;
  int rejected_in_a_row = 0;
  while (next < stops.size()) {
    const S target = stops[next];
    if (t >= target) {
      on_stop(next, y);
      ++next;
      continue;
    }
    const bool to_target = dt >= target - t;
    S h = to_target ? S(target - t) : dt;
    State y1 = y;
    S t1 = t;
    graze = false;
    odeint::controlled_step_result result;
    try {
      result = stepper.try_step(system, y1, t1, h);
    } catch (const odeint::step_adjustment_error& e) {
      throw core::SolverError(
          solver_name, static_cast<double>(t), counters.steps,
          std::string("Bulirsch-Stoer cannot reach the tolerance: ") + e.what());
    }
    if (result == odeint::fail) {
      dt = h;
      if (++rejected_in_a_row > 500) {
        throw core::SolverError(solver_name, static_cast<double>(t), counters.steps,
                                "500 rejected steps in a row");
      }
      continue;
    }
    rejected_in_a_row = 0;
    const S used = t1 - t;
    if (to_target && used >= target - t) t1 = target;  // land exactly on the stop
    model.switching_functions(t1, y1, g1);
    std::size_t first = m;
    for (std::size_t j = 0; j < m; ++j) {
      if (changed(g0, g1, j)) {
        first = j;
        break;
      }
    }
    if (first == m) {
      if (graze && used > S(64) * eps * (abs(t) + S(1))) {
        dt = used / 2;  // a switch inside the step whose ends agree: retry shorter
        stepper.reset();
        continue;
      }
      ++counters.steps;
      t = t1;
      y.swap(y1);
      g0.swap(g1);
      dt = h;  // the controller's proposal for the next step
      continue;
    }
    // Locate the earliest sign change among the functions that changed over [t, t1].
    S best_t = t1;
    State best_y = y1;
    std::size_t best_j = first;
    for (std::size_t j = first; j < m; ++j) {
      if (!changed(g0, g1, j)) continue;
      S lo = t, hi = t1;
      S f_lo = g0[j], f_hi = g1[j];
      State y_hi = y1;
      const bool far_negative = g1[j] < S(0);
      int side = 0;
      for (int iteration = 0; iteration < 400; ++iteration) {
        if (hi - lo <= S(4) * eps * abs(hi)) break;
        S mid = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        // Every fourth iteration, and whenever regula falsi leaves the bracket, bisect: the
        // bracket then at least halves regularly.
        if (!(mid > lo && mid < hi) || iteration % 4 == 3) mid = lo + (hi - lo) / 2;
        if (!(mid > lo && mid < hi)) break;
        const State ym = state_at(y, t, mid);
        model.switching_functions(mid, ym, gm);
        const bool far_side = (gm[j] < S(0)) == far_negative;
        if (far_side) {
          hi = mid;
          f_hi = gm[j];
          y_hi = ym;
          if (side == 1) f_lo /= 2;
          side = 1;
        } else {
          lo = mid;
          f_lo = gm[j];
          if (side == -1) f_hi /= 2;
          side = -1;
        }
      }
      if (hi < best_t) {
        best_t = hi;
        best_y = std::move(y_hi);
        best_j = j;
      }
    }
    ++counters.steps;
    ++counters.events;
    const bool to_negative = g1[best_j] < S(0);
    t = best_t;
    y.swap(best_y);
    model.switching_functions(t, y, g0);
    stepper.reset();
    dt = std::max(S(t - t1 + used), S(64) * eps * (abs(t) + S(1)));
    on_event(SwitchEvent<S>{t, static_cast<int>(best_j), to_negative}, y);
  }
}

}  // namespace flexref::precision::detail
