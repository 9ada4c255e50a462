#pragma once
/// \file odeint_reference.hpp
/// A reference solution for the scheme tests, independent of the schemes and of the
/// SUNDIALS drivers: Boost.Odeint's controlled Runge–Kutta–Fehlberg 7(8) on the quasi-velocity
/// ODE form (reference::OdeForm: 13 states per free body, 7 per pivot body), integrated piece by
/// piece between the model's load discontinuities with t_segment inside each piece, stepping
/// exactly onto every output time (integrate_times adjusts the steps; no interpolation), and
/// the Euler parameters renormalized at the piece ends (unpack normalizes them at output).
#include <boost/numeric/odeint.hpp>
#include <cstddef>
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"
#include "reference/ode_form.hpp"

namespace flexref::testing {

inline core::Trajectory odeint_reference(const core::Model& model,
                                         const std::vector<double>& output_times,
                                         double tolerance) {
  namespace odeint = boost::numeric::odeint;
  using Vector = std::vector<double>;
  const reference::OdeForm ode(model);
  reference::OdeForm::Scratch scratch = ode.make_scratch();
  Vector y(static_cast<std::size_t>(ode.size()));
  ode.pack(model.initial_state(), y.data());

  const double t0 = output_times.front();
  const double t_end = output_times.back();
  std::vector<double> breaks{t0};
  for (double d : model.discontinuities()) {
    if (d > t0 && d < t_end) breaks.push_back(d);
  }
  breaks.push_back(t_end);

  core::Trajectory trajectory;
  trajectory.times = output_times;
  trajectory.states.assign(output_times.size(), model.initial_state());
  std::size_t next_output = 1;

  for (std::size_t piece = 0; piece + 1 < breaks.size(); ++piece) {
    const double a = breaks[piece];
    const double b = breaks[piece + 1];
    const double t_segment = 0.5 * (a + b);
    std::vector<double> times{a};
    for (std::size_t k = next_output; k < output_times.size() && output_times[k] < b; ++k) {
      if (output_times[k] > a) times.push_back(output_times[k]);
    }
    times.push_back(b);
    auto system = [&](const Vector& x, Vector& dxdt, double t) {
      ode.rhs(core::LoadContext{t, t_segment}, x.data(), dxdt.data(), scratch);
    };
    auto observer = [&](const Vector& x, double t) {
      if (next_output < output_times.size() && t == output_times[next_output]) {
        ode.unpack(t, x.data(), trajectory.states[next_output]);
        ++next_output;
      }
    };
    odeint::integrate_times(
        odeint::make_controlled(tolerance, tolerance, odeint::runge_kutta_fehlberg78<Vector>()),
        system, y, times.begin(), times.end(), 1e-4 * (b - a), observer);
    ode.normalize_euler_parameters(y.data());
  }
  return trajectory;
}

}  // namespace flexref::testing
