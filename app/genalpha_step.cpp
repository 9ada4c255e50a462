#include "app/genalpha_step.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "app/step_advice.hpp"
#include "constraint/ideal_joints.hpp"
#include "core/element_text.hpp"
#include "core/step_limit.hpp"
#include "reference/method_choice.hpp"

namespace flexref::app {
namespace {

/// Keeps the fastest rate and what sets it.
struct Fastest {
  double rate = 0.0;
  std::string what;
  void consider(double omega, const std::string& why) {
    if (std::isfinite(omega) && std::abs(omega) > rate) {
      rate = std::abs(omega);
      what = why;
    }
  }
};

/// A drive law's rates: its (final) rate for an angle, and 2π/T_s for a spin-up.
void consider_law(Fastest& fastest, const core::AngleLaw& law, bool angle, const std::string& of) {
  if (angle) fastest.consider(law.rate, "the rate of " + of);
  if (law.kind == core::AngleLaw::Kind::kSpinUp && law.rate != 0.0) {
    fastest.consider(
        2.0 * std::numbers::pi / law.spin_up_time,
        "2 pi/T_s of the spin-up of " + of + " over T_s = " + short_text(law.spin_up_time) + " s");
  }
}

}  // namespace

double genalpha_period_error_coefficient(double rho_inf) {
  const double d = (1.0 - rho_inf) / (1.0 + rho_inf);  // α_f − α_m
  return 1.0 / 12.0 + 0.375 * d * d;
}

GenalphaStepAdvice genalpha_step_advice(const core::Model& model, const std::vector<double>& times,
                                        double rho_inf) {
  Fastest fastest;
  const std::span<const core::Body> bodies(model.bodies());
  for (const core::PenaltyMode& m : core::penalty_modes(model)) {
    if (m.label.ends_with(" friction")) continue;  // a damper: contact/gap_support.cpp
    fastest.consider(m.frequency, m.label + " (omega = sqrt(k/m_eff))");
  }
  const core::State s0 = model.initial_state();
  for (int i = 0; i < model.num_bodies(); ++i) {
    const core::Body& b = model.body(i);
    const std::string body = core::body_text(i, bodies);
    if (b.is_prescribed()) {
      consider_law(fastest, b.description().prescribed.law, true, "the prescribed " + body);
    } else {
      fastest.consider(s0[static_cast<std::size_t>(i)].w_WB_B.norm(), "|W| of " + body + " at t0");
    }
  }
  if (const auto* joints = dynamic_cast<const constraint::IdealJoints*>(model.constraints())) {
    for (const constraint::IdealJointSpec& j : joints->joints()) {
      if (!j.drive.active) continue;
      consider_law(fastest, j.drive.law, j.type == constraint::JointType::kRevolute,
                   "the drive of joint '" + j.name + "'");
    }
  }
  const double spacing = reference::mean_output_spacing(times);
  const reference::StiffnessSummary summary = reference::summarize_stiffness(model, spacing);
  if (!summary.stiff_oscillatory()) {
    fastest.consider(summary.resolved_rate,
                     "the motion linearized at t0 (the largest rate of the ODE Jacobian's "
                     "oscillations and growth)");
  }
  const double cut = reference::kStiffnessRatio * summary.accuracy_rate;
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Eigen::VectorXd& w = model.body(i).natural_frequencies();
    for (Eigen::Index k = 0; k < w.size(); ++k) {
      if (w(k) <= cut) {
        fastest.consider(w(k), "mode " + std::to_string(k + 1) + " of flexible " +
                                   core::body_text(i, bodies) + " (frame held fixed)");
      }
    }
  }
  GenalphaStepAdvice advice;
  advice.rate = fastest.rate;
  advice.what = fastest.what;
  if (!(fastest.rate > 0.0)) {
    advice.bound = std::numeric_limits<double>::infinity();
    return advice;
  }
  advice.bound =
      std::sqrt(kGenalphaPeriodError / genalpha_period_error_coefficient(rho_inf)) / fastest.rate;
  // No floor of its own: a step below what double precision resolves over the run is off the
  // grid (lie::validate_step_grid), so round_step never returns one.
  advice.step = round_step(model, advice.bound, times, 0.0);
  return advice;
}

}  // namespace flexref::app
