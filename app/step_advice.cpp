#include "app/step_advice.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/step_limit.hpp"
#include "lie/rotational_stability.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"

namespace flexref::app {

std::string short_text(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

namespace {

/// The bound a suggested step keeps to, and what sets it.
struct Bound {
  double h = 0.0;
  std::string why;
};

Bound step_bound(const core::Model& model, const std::string& scheme, double dt, double spin) {
  Bound bound{0.5 * dt, "half the step that failed"};
  // Half the explicit step limit: at the limit itself central differences are marginally
  // stable (h ω = 2 has a growing mode).
  const core::StepLimit limit = core::explicit_step_limit(model);
  if (limit.bounded() && 0.5 * limit.h < bound.h) {
    bound = {0.5 * limit.h,
             "half the explicit step limit " + short_text(limit.h) + " s of " + limit.what};
  }
  // A tenth of the rotational limit: below its limit C2's energy still drifts secularly, and
  // long runs break the balance (free_spin's body at 1000× its spin: at h|W| = 0.1 after
  // 1.3e6 steps; at 0.04 it stays within 0.6 % over 5e6).
  const double rotational = lie::rotational_stability_limit(scheme);
  if (rotational > 0.0 && spin > 0.0 && 0.1 * rotational / spin < bound.h) {
    bound = {0.1 * rotational / spin,
             "a tenth of " + scheme + "'s rotational stability limit h|W| = " +
                 short_text(rotational) + " at |W| = " + short_text(spin) + " rad/s"};
  }
  return bound;
}

bool on_grid(const core::Model& model, double h, const std::vector<double>& times) {
  try {
    lie::validate_step_grid(model, h, times);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

}  // namespace

std::string rotational_step_warning(const core::Model& model, const std::string& scheme, double dt,
                                    const core::State& state, double t) {
  const double limit = lie::rotational_stability_limit(scheme);
  const lie::SpinRate spin = lie::largest_spin(model, state);
  if (!(limit > 0.0) || spin.body < 0 || !(dt * spin.w > limit)) return {};
  std::ostringstream out;
  out << "step " << short_text(dt) << " s times |W| = " << short_text(spin.w) << " rad/s of body '"
      << model.body(spin.body).name() << "' at t = " << short_text(t)
      << " s is h|W| = " << short_text(dt * spin.w) << ", above " << scheme
      << "'s rotational stability limit " << limit
      << " (measured on a torque-free body, lie/rotational_stability.hpp): the run may blow up";
  return out.str();
}

std::string stiff_mode_warning(const std::string& scheme, double dt, const core::PenaltyMode& m) {
  if (dt <= m.step_limit) return {};
  const bool flexible = m.kind == "flexible body";
  const std::string what =
      flexible ? "the highest modes of flexible body " + m.label + " are" : m.label + " is";
  std::ostringstream out;
  out << "step " << dt << " s exceeds 2/omega" << (flexible ? "_max" : "") << " = " << m.step_limit
      << " s of " << (flexible ? "flexible body " : "") << m.label << " (omega"
      << (flexible ? "_max" : "") << " = " << m.frequency
      << " rad/s, h omega = " << short_text(dt * m.frequency) << "): ";
  const std::vector<std::string> hybrid = lie::builtin_scheme_names();
  if (std::find(hybrid.begin(), hybrid.end(), scheme) != hybrid.end()) {
    out << scheme << " integrates translation and modes by explicit central differences, "
        << "unstable above this step, and " << what << " not resolved";
  } else if (scheme == "genalpha") {
    out << "genalpha is implicit and stays stable, but " << what
        << " not resolved (numerically damped at rho_inf < 1)";
  } else {
    out << "flexref does not know whether " << scheme
        << " is explicit: an explicit method is unstable above this step, an implicit one does "
           "not resolve it";
  }
  return out.str();
}

double round_step(const core::Model& model, double bound, const std::vector<double>& times,
                  double smallest) {
  if (!(bound > 0.0) || !std::isfinite(bound)) return 0.0;
  // {5, 2, 1}·10^k from the decade of the bound downward.
  double decade = std::pow(10.0, std::floor(std::log10(bound)));
  for (int k = 0; k < 30; ++k, decade /= 10.0) {
    for (const double m : {5.0, 2.0, 1.0}) {
      // The value as printed, so that the step the user types is the one checked here.
      const double h = std::stod(short_text(m * decade));
      if (h <= bound && h >= smallest && on_grid(model, h, times)) return h;
    }
  }
  return 0.0;
}

double suggested_step(const core::Model& model, const std::string& scheme, double dt,
                      const std::vector<double>& times, double spin) {
  return round_step(model, step_bound(model, scheme, dt, spin).h, times, 1e-6 * dt);
}

std::string verified_step_advice(const core::Model& model, const std::string& scheme, double dt,
                                 const std::vector<double>& times, double spin,
                                 const RunAttempt& failed,
                                 const std::function<RunAttempt(double)>& retry) {
  double h = suggested_step(model, scheme, dt, times, spin);
  // A check that would cost more than kVerifyCostRatio times the failed run (a step hundreds of
  // times smaller, e.g. h|W| ≤ 0.58 at 1e6 rad/s) is not run behind the user's back: the advice
  // is the bound's, and says so.
  constexpr double kVerifyCostRatio = 32.0;
  if (h > 0.0 && dt / h > kVerifyCostRatio) {
    return "; nothing was written: use --dt " + short_text(h) + " (at most " +
           step_bound(model, scheme, dt, spin).why + "; not checked: a run at that step costs " +
           short_text(dt / h) + " times this one)";
  }
  double previous = dt;
  std::string tried;
  for (int attempt = 0; attempt < 2 && h > 0.0; ++attempt) {
    const RunAttempt a = retry(h);
    if (a.passed) {
      return "; nothing was written: use --dt " + short_text(h) + " (at most " +
             step_bound(model, scheme, previous, spin).why +
             "; checked: a run at that step passes)";
    }
    const bool breach =
        !std::isnan(failed.change) && !std::isnan(a.change) && a.quantity == failed.quantity;
    if (breach && a.change > kUnshrunkChange * failed.change) {
      return "; nothing was written; a smaller step does not help: at --dt " + short_text(h) +
             " the " + a.quantity + " changed by " + short_text(100.0 * a.change) +
             " % of its scale, against " + short_text(100.0 * failed.change) + " % at --dt " +
             short_text(dt) +
             " — the change does not shrink with the step, so the step is not its cause";
    }
    if (std::isnan(failed.change) && std::isnan(a.change) &&
        std::abs(a.time - failed.time) <= 2.0 * dt) {
      return "; nothing was written; a smaller step does not help: at --dt " + short_text(h) +
             " the run fails at the same time (t = " + short_text(a.time) + " s): " + a.why;
    }
    tried += (tried.empty() ? "" : ", ") + short_text(h);
    previous = h;
    h = suggested_step(model, scheme, h, times, spin);
  }
  return tried.empty() ? std::string()
                       : "; nothing was written; no smaller step passed (tried --dt " + tried + ")";
}

std::string step_advice(const core::Model& model, const std::string& scheme, double dt,
                        const std::vector<double>& times, double spin) {
  const double h = suggested_step(model, scheme, dt, times, spin);
  if (!(h > 0.0)) return {};
  return "; nothing was written: use --dt " + short_text(h) + " (at most " +
         step_bound(model, scheme, dt, spin).why + ")";
}

}  // namespace flexref::app
