#pragma once
/// \file attitude_ode.hpp
/// Independent numerical solutions for the exact-solution tests: the 7-dimensional attitude
/// ODE of one rigid body about a fixed point, θ̇ = ½ θ ⊗ (0, ω̄), J ω̄̇ = T(θ) − ω̄ × J ω̄,
/// integrated by Boost.Odeint's controlled RKF7(8), and irregular sample times.
#include <Eigen/Core>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <vector>

#include "rotation/euler_parameters.hpp"

namespace flexref::testing {

/// [θ0..θ3, ω̄1..ω̄3] (std::array triggers a spurious -Wuninitialized inside odeint).
using AttitudeState = std::vector<double>;

/// The state at each time; torque_B(θ) is the body-frame torque about the fixed point.
template <typename TorqueB>
std::vector<AttitudeState> integrate_attitude(const Eigen::Matrix3d& inertia_B, TorqueB torque_B,
                                              const rotation::EulerParameters& theta0,
                                              const Eigen::Vector3d& w0_B,
                                              const std::vector<double>& times, double tolerance,
                                              double first_step) {
  namespace odeint = boost::numeric::odeint;
  const Eigen::Matrix3d inertia_inverse = inertia_B.inverse();
  const auto rhs = [&](const AttitudeState& x, AttitudeState& dxdt, double) {
    const rotation::EulerParameters theta(x[0], x[1], x[2], x[3]);
    const Eigen::Vector3d w(x[4], x[5], x[6]);
    const rotation::EulerParameters theta_rate = rotation::euler_parameter_rate(theta, w);
    const Eigen::Vector3d w_rate = inertia_inverse * (torque_B(theta) - w.cross(inertia_B * w));
    dxdt = {theta_rate(0), theta_rate(1), theta_rate(2), theta_rate(3),
            w_rate(0),     w_rate(1),     w_rate(2)};
  };
  using Stepper = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<AttitudeState>>;
  std::vector<AttitudeState> out;
  AttitudeState x{theta0(0), theta0(1), theta0(2), theta0(3), w0_B(0), w0_B(1), w0_B(2)};
  odeint::integrate_times(Stepper(Stepper::error_checker_type(tolerance, tolerance)), rhs, x,
                          times.begin(), times.end(), first_step,
                          [&out](const AttitudeState& s, double) { out.push_back(s); });
  return out;
}

/// count + 1 times on [0, t_end], with a sine wobble of 0.3 % inside so that no sample hits a
/// symmetric point of the motion.
inline std::vector<double> sample_times(double t_end, int count) {
  std::vector<double> times;
  for (int i = 0; i <= count; ++i) {
    const double s = static_cast<double>(i) / count;
    times.push_back(t_end * (s + 0.003 * std::sin(7.0 * s) * (i > 0 && i < count ? 1.0 : 0.0)));
  }
  return times;
}

}  // namespace flexref::testing
