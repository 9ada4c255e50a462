#pragma once
/// \file switching_predictor.hpp
/// A cap on the next step of an explicit one-step reference (Odeint's RKF7(8), ARKODE's
/// Fehlberg 13-7-8) near a zero of a switching function (contact onset or release), so that a
/// step that reaches a contact ends just past it, where the sign test sees it, instead of
/// stepping over the whole impact: the Fehlberg 7(8) error estimates compare only the stages at
/// a step's ends and do not see a stiff contact force that acted in between (measured on
/// bouncing_ball: a step of 0.13 s from just after an apex through the next impact was
/// accepted, and the ball left with 100 m of height).
///
/// The prediction: the second-order Taylor path P(τ) = x + τ ẋ + ½ τ² ẍ from the step's start
/// (ẍ = J ẋ by a forward difference of the right-hand side along ẋ; exact for ballistic
/// positions), the quadratic q_k(s), s = τ/h, through g_k at P(0), P(h/2), P(h), and the cap
/// 1.1 h s* at the first zero s* ∈ (0, 1] of any q_k where it changes side. A prediction that
/// falls short costs one more step; a contact inside a step is then still caught by the
/// drivers' own checks (Odeint's double-crossing candidates, the step-doubling test in
/// contact). One right-hand side and two switching evaluations per call; allocates nothing.
#include <functional>
#include <span>
#include <vector>

#include "reference/ode_form.hpp"

namespace flexref::reference {

class SwitchingPredictor {
 public:
  /// f(t, x, out): the right-hand side; returns false when it is not finite.
  using Rhs = std::function<bool(double, const double*, double*)>;

  explicit SwitchingPredictor(const OdeForm& form);

  /// The cap (≤ h) on a step of length h from (t, x) with ẋ = xdot and switching functions
  /// g0 at x; h itself when no predicted path changes side within it or the prediction is
  /// not finite.
  double cap(double t, const double* x, const double* xdot, std::span<const double> g0, double h,
             double t_segment, const Rhs& rhs, OdeForm::Scratch& scratch);

  /// The smallest s > 0 where g0 + b s + c s² changes side (g0 ≠ 0), or 0 when there is none.
  static double first_zero(double g0, double b, double c);

 private:
  void switching_at(double t, double t_segment, OdeForm::Scratch& scratch,
                    std::vector<double>& g) const;

  const OdeForm* form_;
  std::vector<double> x_probe_, xdot_probe_;
  std::vector<double> g_mid_, g_end_;
};

}  // namespace flexref::reference
