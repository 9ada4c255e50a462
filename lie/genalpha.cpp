#include "lie/genalpha.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "lie/scheme_support.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::lie {

GenAlphaStepper::GenAlphaStepper(const core::Model& model, const GenAlphaParameters& parameters)
    : model_(model),
      system_(model, parameters),
      state_(model.initial_state()),
      next_(state_),
      ws_(model.make_workspace()),
      tracker_(model.make_constraint_tracker()),
      wear_(model),
      acc_(model.make_accelerations()),
      vdot_(Eigen::VectorXd::Zero(system_.body_unknowns())),
      a_(vdot_),
      vdot_next_(vdot_),
      a_next_(vdot_),
      lambda_hat_(Eigen::VectorXd::Zero(system_.multiplier_count())),
      lambda_saved_(lambda_hat_),
      z_(Eigen::VectorXd::Zero(system_.size())),
      r_(z_),
      dz_(z_),
      z_base_(z_),
      pattern_rows_(1, -1) {}

double GenAlphaStepper::force_evaluations_per_step() const {
  if (steps_ == 0) return 1.0 + system_.matrix_evaluations();
  return static_cast<double>(system_.evaluations() - evaluations_at_start_) /
         static_cast<double>(steps_);
}

void GenAlphaStepper::initialize(double t0, const core::State& state) {
  if (state.size() != state_.size()) {
    throw std::invalid_argument(
        "genalpha: the state has a different number of bodies than the model");
  }
  time_ = t0;
  state_ = state;
  next_ = state;
  last_h_ = 0.0;
  initialized_ = false;
  if (system_.multiplier_count() > 0) {
    tracker_ = model_.make_constraint_tracker();
    system_.set_active_rows(model_.independent_rows());
    const std::string singular = track_joints(t0, state_);
    if (!singular.empty()) throw core::SingularConfigurationError("", t0, singular);
  }
  restart();
  // t_segment = t0 evaluated the branch on the right of t0, the first step's own; a load
  // discontinuity at t0 itself restarts there (starts_on_discontinuity). The perturbed start
  // needs h: the first step sets a_0.
  if (system_.parameters().perturbed_start) {
    initialized_ = false;
    restart_pending_ = true;
  } else {
    restart_pending_ = false;
  }
  evaluations_at_start_ = system_.evaluations();
  newton_iterations_ = 0;
  max_newton_iterations_ = 0;
  steps_ = 0;
}

void GenAlphaStepper::initialize_with_auxiliary(double t0, const core::State& state,
                                                const Eigen::VectorXd& a0) {
  initialize(t0, state);
  if (a0.size() != a_.size()) {
    throw std::invalid_argument("genalpha: a0 must have 6 + n_b entries per body b");
  }
  a_ = a0;
  restart_pending_ = false;
  initialized_ = true;
}

void GenAlphaStepper::restart() {
  matrix_valid_ = false;
  // Consistent accelerations from the equations at t_n (right limit: the branch of loads that
  // starts there), and a_n = v̇_n; with joints, λ_n from the index-1 solve as the predictor.
  const double segment = time_ + (last_h_ > 0.0 ? 0.5 * last_h_ : 0.0);
  model_.compute_accelerations(core::LoadContext{time_, segment}, state_, tracker_, ws_, acc_);
  if (system_.multiplier_count() > 0) {
    // λ_n on the Newton system's rows (the solve may have chosen others: the same reactions,
    // F = −J_aᵀ λ_a, on the system's basis of the rows' span); scaled to β h² λ_n by the next
    // step.
    lambda_hat_ = model_.joint_multipliers(ws_).on_rows(system_.active_rows());
    lambda_unscaled_ = true;
  }
  wear_.start(core::LoadContext{time_, segment}, state_, ws_);
  system_.stack_accelerations(acc_, vdot_);
  if (!initialized_) {
    a_ = vdot_;
    if (system_.parameters().perturbed_start && last_h_ > 0.0) perturbed_start(segment);
  }
  initialized_ = true;
  restart_pending_ = false;
}

void GenAlphaStepper::perturbed_start(double segment) {
  // a_0 = v̇(t_0 + Δ h), Δ = α_m − α_f (Arnold, Brüls & Cardona): the accelerations at the state
  // extrapolated by Taylor, q_0 exp(Δh v_0 + ½ (Δh)² v̇_0), v_0 + Δh v̇_0, which is O(h²) from
  // the exact one.
  const GenAlphaParameters& p = system_.parameters();
  const double shift = (p.alpha_m - p.alpha_f) * last_h_;
  for (std::size_t b = 0; b < state_.size(); ++b) {
    const core::BodyState& s = state_[b];
    core::BodyState& s1 = next_[b];
    s1 = s;
    const auto o = static_cast<Eigen::Index>(system_.offset(static_cast<int>(b)));
    if (model_.body(static_cast<int>(b)).is_free()) {
      s1.p_WBr = s.p_WBr + shift * s.v_WBr + (0.5 * shift * shift) * vdot_.segment<3>(o);
      s1.v_WBr = s.v_WBr + shift * vdot_.segment<3>(o);
    }
    s1.theta_WB = rotation::quaternion_multiply(
        s.theta_WB, rotation::exp_quaternion(shift * s.w_WB_B +
                                             (0.5 * shift * shift) * vdot_.segment<3>(o + 3)));
    detail::renormalize_unit_product(s1.theta_WB);
    s1.w_WB_B = s.w_WB_B + shift * vdot_.segment<3>(o + 3);
    const Eigen::Index modes = s.q_f.size();
    if (modes > 0) {
      s1.q_f = s.q_f + shift * s.qd_f + (0.5 * shift * shift) * vdot_.segment(o + 6, modes);
      s1.qd_f = s.qd_f + shift * vdot_.segment(o + 6, modes);
    }
  }
  model_.apply_prescribed_motion(time_ + shift, next_);
  model_.compute_accelerations(core::LoadContext{time_ + shift, segment}, next_, tracker_, ws_,
                               acc_);
  system_.stack_accelerations(acc_, a_);
}

Eigen::VectorXd GenAlphaStepper::multipliers() const {
  if (lambda_unscaled_ || last_h_ <= 0.0) return lambda_hat_;
  const double bh2 = system_.parameters().beta * last_h_ * last_h_;
  return lambda_hat_ / bh2;
}

StepStatus GenAlphaStepper::step(double h) {
  const double t_n = time_;
  // A failed step leaves no matrix behind: it may have been assembled at a diverging iterate.
  const auto fail = [this](std::string message) {
    matrix_valid_ = false;
    return StepStatus{false, std::move(message)};
  };
  if (restart_pending_ || detail::starts_on_discontinuity(model_.discontinuities(), t_n, h)) {
    last_h_ = h;
    restart();
  }
  const double bh2 = system_.parameters().beta * h * h;
  // λ̂ = β h² λ: the predictor carries λ_n over; rescale when h changed.
  if (system_.multiplier_count() > 0) {
    const double previous = system_.parameters().beta * last_h_ * last_h_;
    if (lambda_unscaled_) {
      lambda_hat_ *= bh2;
      lambda_unscaled_ = false;
    } else if (previous > 0.0 && previous != bh2) {
      lambda_hat_ *= bh2 / previous;
    }
  }
  // The worn depths the step's loads see: h_n + Δt ḣ_n.
  wear_.predict(state_, h, next_);
  system_.set_wear_depth(next_.wear_depth);
  system_.begin_step(t_n, h, state_, vdot_, a_);
  system_.predictor(lambda_hat_, z_);

  bool converged = false;
  // The factored matrix of an earlier step is reused while Newton contracts fast with it (it
  // changes by O(h) per step); a new step length or a restart assembles anew.
  bool assembled = matrix_valid_ && matrix_h_ == h;
  int reassemblies = 0;
  int iterations = 0;
  int backtracks = 0;
  double previous = std::numeric_limits<double>::infinity();
  double merit_base = std::numeric_limits<double>::infinity();  // ‖r(z_base_)‖²
  double fraction = 1.0;                                        // of dz_ taken from z_base_
  bool fresh = false;  // dz_ was computed with a matrix assembled at z_base_
  detail::GenAlphaResidualNorm norm;
  while (iterations < kMaxNewtonIterations) {
    norm = system_.residual(z_, r_);
    const double merit = r_.squaredNorm();
    // The line search: a fresh correction that does not decrease ‖r‖² enough (or leaves the
    // model's domain) is halved, from the iterate it was computed at.
    const bool insufficient =
        !norm.finite || !(merit <= (1.0 - 2.0 * kArmijo * fraction) * merit_base);
    if (fresh && insufficient && norm.relative > detail::kNewtonTolerance &&
        backtracks < kMaxBacktracks) {
      ++backtracks;
      fraction *= 0.5;
      z_ = z_base_ - fraction * dz_;
      continue;
    }
    if (!norm.finite) return fail(detail::non_finite_failure("genalpha", t_n, h));
    const bool slow = assembled && norm.relative > kSlowContraction * previous;
    fresh = false;
    // Past kMaxReassemblies a matrix is still assembled where the iteration makes no progress at
    // all: a stale matrix then cycles (a contact's onset or release between two iterates).
    if (!assembled || (slow && (reassemblies < kMaxReassemblies || !(norm.relative < previous)) &&
                       !detail::newton_stagnated(norm.relative, previous))) {
      reassemblies += assembled ? 1 : 0;
      if (pattern_rows_ != system_.active_rows()) {
        // A new set of rows in force (or the first matrix): a new pattern, ordered once.
        pattern_rows_ = system_.active_rows();
        system_.make_iteration_matrix(S_);
        lu_.analyze(static_cast<int>(S_.rows()), S_.outerIndexPtr(), S_.innerIndexPtr());
      }
      system_.iteration_matrix(z_, S_);
      if (!std::isfinite(S_.coeffs().sum())) {
        return fail(detail::non_finite_failure("genalpha", t_n, h));
      }
      if (!lu_.factor(S_.valuePtr())) {
        std::ostringstream message;
        message.precision(17);
        message << "genalpha: singular Newton matrix in the step from t = " << t_n
                << " with h = " << h;
        return fail(message.str());
      }
      assembled = true;
      fresh = true;
      matrix_valid_ = true;
      matrix_h_ = h;
    }
    // z ← z − S⁻¹ r   (also after the test has passed: the last correction costs no evaluation)
    dz_ = r_;
    lu_.solve(dz_.data());
    z_base_ = z_;
    merit_base = merit;
    fraction = 1.0;
    backtracks = 0;
    z_ -= dz_;
    ++iterations;
    // A residual that repeats bit for bit is at the round-off floor of its own terms: the
    // corrections no longer change what it resolves (a flexible body near rest, whose modal
    // rows' terms cancel to below any scale the test knows of: 7e-10 relative on
    // flexible_spinner's first step). Accepted up to kRepeatedResidualFloor.
    const bool repeated = norm.relative == previous && norm.relative <= kRepeatedResidualFloor;
    if (norm.relative <= detail::kNewtonTolerance ||
        detail::newton_stagnated(norm.relative, previous) || repeated) {
      converged = true;
      break;
    }
    previous = norm.relative;
  }
  if (!converged) {
    return fail(newton_failure_message(t_n, h, norm.relative, iterations, norm.worst_body));
  }
  system_.state_at(z_, next_, vdot_next_, a_next_);
  if (!detail::all_finite(next_) || !std::isfinite(z_.sum())) {
    return fail(detail::non_finite_failure("genalpha", t_n, h));
  }
  wear_.correct(core::LoadContext{t_n + h, t_n + 0.5 * h}, state_, h, next_, ws_);
  if (system_.multiplier_count() > 0) {
    // λ̂_{n+1} on the rows the system solved them for, then the joints at the new state (λ̂_n
    // kept for a failure, which leaves the stepper at the start of the step).
    lambda_saved_ = lambda_hat_;
    lambda_hat_ = z_.tail(system_.multiplier_count());
    const std::string singular = track_joints(t_n + h, next_);
    if (!singular.empty()) {
      lambda_hat_ = lambda_saved_;
      return fail("genalpha: " + singular);
    }
  }
  std::swap(state_, next_);
  wear_.accept();
  std::swap(vdot_, vdot_next_);
  std::swap(a_, a_next_);
  time_ = t_n + h;
  last_h_ = h;
  newton_iterations_ += iterations;
  max_newton_iterations_ = std::max(max_newton_iterations_, iterations);
  ++steps_;
  return {};
}

std::string GenAlphaStepper::track_joints(double t, const core::State& next) {
  try {
    model_.advance_tracker(t, next, tracker_, ws_);
  } catch (const core::SingularConfigurationError& e) {
    return e.what();
  }
  if (tracker_.rows != system_.active_rows()) {
    // The rows chosen again at `next`: λ̂ on the old rows, as the same generalized reaction
    // there, on the new rows; the next Newton system solves for them.
    lambda_hat_ = tracker_.carry(lambda_hat_, system_.active_rows());
    system_.set_active_rows(tracker_.rows);
    matrix_valid_ = false;
  }
  return {};
}

std::string GenAlphaStepper::newton_failure_message(double t_n, double h, double residual,
                                                    int iterations, int body) const {
  std::string message = detail::newton_failure("genalpha", t_n, h, residual, iterations, body);
  if (model_.has_constraints()) {
    // A Newton iteration that fails where the joints' rows lose rank ahead cannot be helped by a
    // smaller step: the singular configuration is named instead.
    const std::string ahead = model_.singular_configuration_ahead(t_n, state_, 2.0 * h);
    if (!ahead.empty()) {
      message +=
          ": the mechanism is at a singular configuration, which no smaller step crosses — " +
          ahead;
    }
  }
  return message;
}

}  // namespace flexref::lie
