/// \file reference_cross_check_test.cpp
/// The reference solvers against each other (docs/design/schemes.md, "Reference integrators"):
/// IDA on the DAE form against CVODE on the ODE form (same physics, different equations), the
/// three solvers pairwise on book_toss, and the load switch of the rectangular pulse, checked
/// against the exact angular-momentum balance.
#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <memory>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/force_element.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/reference_solver.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/solver_options.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

using testing::with_rtol;

using SolveFunction = ReferenceRun (*)(const core::Model&, const std::vector<double>&,
                                       const SolverOptions&);

/// book_toss's torque (docs/design/scenes.md, tests/support/test_problems.hpp): world (0.2, 0, 0.2)
/// N·m on [0, 0.1).
const Eigen::Vector3d kBookTorque_W(0.2, 0.0, 0.2);
constexpr double kPulse = 0.1;

/// book_toss (sin² pulse) or book_toss_step (rectangular pulse).
core::Model book_toss(bool rectangular) {
  return rectangular ? testing::book_toss_step() : testing::book_toss();
}

/// The rectangular pulse as a load that hides its switch from the drivers: no
/// append_discontinuities, and the branch is chosen by t itself. What a driver integrates when
/// it does not stop at the switch.
class HiddenSwitchTorque final : public core::ForceElement {
 public:
  void add_wrenches(const core::LoadContext& context,
                    std::span<const core::BodyKinematics> /*bodies*/,
                    std::span<core::Wrench> wrenches) const override {
    if (context.t < kPulse) wrenches[0].tau_Br_W += kBookTorque_W;
  }
  int max_body_index() const override { return 0; }
  std::string describe() const override { return "rectangular torque pulse, switch hidden"; }
};

core::Model book_toss_hidden_switch() {
  std::vector<core::Body> bodies;
  bodies.emplace_back(testing::rigid_body("book", 1.0, {1.0, 2.0, 2.8}, {0.0, 10.0, 0.0}));
  testing::Elements elements;
  elements.push_back(std::make_unique<HiddenSwitchTorque>());
  return core::Model(std::move(bodies), std::move(elements));
}

/// A load whose evaluation throws after t = 0.5, like a tabulated load that runs out of data.
class ThrowingTorque final : public core::ForceElement {
 public:
  void add_wrenches(const core::LoadContext& context,
                    std::span<const core::BodyKinematics> /*bodies*/,
                    std::span<core::Wrench> /*wrenches*/) const override {
    if (context.t > 0.5) throw std::runtime_error("torque table ends at t = 0.5");
  }
  int max_body_index() const override { return 0; }
  std::string describe() const override { return "torque that throws after t = 0.5"; }
};

/// ∫₀ᵗ f for the two pulse shapes: t on the rectangle; t/2 − (d/4π) sin(2πt/d) for sin²(πt/d).
double impulse_fraction(bool rectangular, double t) {
  const double s = std::min(t, kPulse);
  if (rectangular) return s;
  return 0.5 * s -
         kPulse / (4.0 * std::numbers::pi) * std::sin(2.0 * std::numbers::pi * s / kPulse);
}

/// Largest differences over the output times (L∞, docs/design/schemes.md "Error metrics").
struct Difference {
  double position = 0.0;          ///< |Δp_WBr|, m
  double angle = 0.0;             ///< geodesic angle, rad
  double velocity = 0.0;          ///< |Δv_WBr|, m/s
  double angular_velocity = 0.0;  ///< |Δω̄|, rad/s
};

Difference difference(const ReferenceRun& a, const ReferenceRun& b) {
  REQUIRE(a.trajectory.times == b.trajectory.times);
  Difference d;
  for (std::size_t k = 0; k < a.trajectory.states.size(); ++k) {
    const core::BodyState& x = a.trajectory.states[k][0];
    const core::BodyState& y = b.trajectory.states[k][0];
    d.position = std::max(d.position, (x.p_WBr - y.p_WBr).norm());
    d.angle = std::max(d.angle, rotation::geodesic_angle(x.theta_WB, y.theta_WB));
    d.velocity = std::max(d.velocity, (x.v_WBr - y.v_WBr).norm());
    d.angular_velocity = std::max(d.angular_velocity, (x.w_WB_B - y.w_WB_B).norm());
  }
  return d;
}

/// Largest |π(t_k) − π(0) − Γ ∫₀^{t_k} f| over the outputs: the exact angular-momentum balance
/// of a free body under a pure world torque (no other load).
double momentum_balance_error(const core::Model& model, const ReferenceRun& run, bool rectangular) {
  const Eigen::Vector3d momentum0 = model.angular_momentum_W(run.trajectory.states.front());
  double error = 0.0;
  for (std::size_t k = 0; k < run.trajectory.states.size(); ++k) {
    const Eigen::Vector3d exact =
        momentum0 + kBookTorque_W * impulse_fraction(rectangular, run.trajectory.times[k]);
    error = std::max(error, (model.angular_momentum_W(run.trajectory.states[k]) - exact).norm());
  }
  return error;
}

}  // namespace

TEST_CASE("IDA (DAE form) and CVODE (ODE form) agree on coulomb_wall", "[ida][cvode]") {
  // The full scene: 100 s (each run takes ~0.1–0.3 s).
  const core::Model model = testing::coulomb_wall();
  const std::vector<double> times = core::output_times(100.0, 0.01);
  const double rtol = 1e-10;
  const ReferenceRun ida = solve_ida(model, times, with_rtol(rtol));
  const ReferenceRun cvode = solve_cvode(model, times, with_rtol(rtol));
  const ReferenceRun ida_tight = solve_ida(model, times, with_rtol(rtol / 100.0));
  const ReferenceRun cvode_tight = solve_cvode(model, times, with_rtol(rtol / 100.0));

  const Difference between = difference(ida, cvode);
  const Difference between_tight = difference(ida_tight, cvode_tight);
  // Each run's error estimate (docs/design/schemes.md): the difference to a run at 100× tighter
  // tolerance, whose own error is ~100× smaller.
  const Difference ida_estimate = difference(ida, ida_tight);
  const Difference cvode_estimate = difference(cvode, cvode_tight);
  CAPTURE(between.position, between.angle, between.velocity, between.angular_velocity);
  CAPTURE(ida_estimate.position, ida_estimate.angle, ida_estimate.velocity,
          ida_estimate.angular_velocity);
  CAPTURE(cvode_estimate.position, cvode_estimate.angle, cvode_estimate.velocity,
          cvode_estimate.angular_velocity);
  CAPTURE(between_tight.position, between_tight.angle, between_tight.velocity,
          between_tight.angular_velocity);

  // (a) Two approximations of one solution differ by at most the sum of their errors; the
  // factor 2 allows each estimate to be low by 2× (the tighter run is not exact, and the error
  // is only roughly proportional to rtol). Measured: the difference is 0.2–0.4 of the sum.
  CHECK(between.position <= 2.0 * (ida_estimate.position + cvode_estimate.position));
  CHECK(between.angle <= 2.0 * (ida_estimate.angle + cvode_estimate.angle));
  CHECK(between.velocity <= 2.0 * (ida_estimate.velocity + cvode_estimate.velocity));
  CHECK(between.angular_velocity <=
        2.0 * (ida_estimate.angular_velocity + cvode_estimate.angular_velocity));

  // (b) The difference is discretization error, not a difference between the two forms of
  // the equations: it shrinks with the tolerance. A 100× tighter rtol must shrink it at least
  // 10× (a tolerance-proportional error shrinks ~100×; measured 20–88×).
  CHECK(between_tight.position <= between.position / 10.0);
  CHECK(between_tight.angle <= between.angle / 10.0);
  CHECK(between_tight.velocity <= between.velocity / 10.0);
  CHECK(between_tight.angular_velocity <= between.angular_velocity / 10.0);

  // (c) A ceiling from the tolerance: each solver takes 1e4–2e4 steps, each committing up to
  // rtol relative, and the flow amplifies a perturbation by up to ~200 over 100 s (measured
  // by perturbing W0 by 1e-9). Local errors of varying sign add like √N:
  // √(2e4) · 1e-10 · 200 ≈ 3e-6 of the O(1) state; ceiling 2e-5 (measured ≤ 5e-6, the linear
  // velocity).
  CHECK(between.position <= 2e-5);
  CHECK(between.angle <= 2e-5);
  CHECK(between.velocity <= 2e-5);
  CHECK(between.angular_velocity <= 2e-5);
}

TEST_CASE("the three solvers agree pairwise on book_toss", "[ida][cvode][arkode][odeint]") {
  const bool rectangular = GENERATE(false, true);
  CAPTURE(rectangular);
  const core::Model model = book_toss(rectangular);
  const std::vector<double> times = core::output_times(10.0, 0.01);
  const ReferenceRun cvode = solve_cvode(model, times, with_rtol(1e-12));
  const ReferenceRun odeint = solve_odeint(model, times, with_rtol(1e-12));
  // IDA at rtol 1e-13: its BDF needs a decade more than CVODE's Adams here (5e-8 rad against
  // Odeint at 1e-14 at rtol 1e-13, 2.7e-7 at 1e-12; reference_targets_test.cpp).
  const ReferenceRun ida = solve_ida(model, times, with_rtol(1e-13));

  // Spin about the intermediate axis: the pulse leaves the book 1e-3 rad/s off the unstable
  // axis, and it flips. An error δ in ω̄ early on moves the flips; perturbing W0 by 1e-12
  // moved ω̄ by up to 9e-8 later (amplification A ≈ 1e5), and the attitude by a tenth of that
  // in rad. CVODE and odeint at rtol 1e-12 commit local errors ~rtol·|ω̄| = 1e-11 rad/s, so
  // A·1e-11 ≈ 1e-6 rad/s is the expected difference; bounds 1e-5 rad/s and 1e-6 rad
  // (measured 2.2e-7 and 2.2e-8 for sin², 9.8e-8 and 9.9e-9 for the rectangle).
  const Difference cvode_odeint = difference(cvode, odeint);
  CAPTURE(cvode_odeint.angle, cvode_odeint.angular_velocity);
  CHECK(cvode_odeint.angular_velocity <= 1e-5);
  CHECK(cvode_odeint.angle <= 1e-6);

  // IDA commits local errors ~rtol·|ω̄| = 1e-12 rad/s at rtol 1e-13, amplified like the others':
  // the same bounds (measured 5.4e-7 rad/s and 5.4e-8 rad against CVODE, 3.1e-7 and 3.1e-8
  // against Odeint for sin², 3.7e-8 and 7.9e-9 at most for the rectangle). Before the DAE form was
  // the quasi-velocity one, IDA needed rtol 1e-14 for 5e-6 rad here.
  const Difference ida_cvode = difference(ida, cvode);
  const Difference ida_odeint = difference(ida, odeint);
  CAPTURE(ida_cvode.angle, ida_cvode.angular_velocity, ida_odeint.angle,
          ida_odeint.angular_velocity);
  CHECK(ida_cvode.angular_velocity <= 1e-5);
  CHECK(ida_cvode.angle <= 1e-6);
  CHECK(ida_odeint.angular_velocity <= 1e-5);
  CHECK(ida_odeint.angle <= 1e-6);
}

TEST_CASE("book_toss angular momentum follows the applied impulse exactly",
          "[ida][cvode][arkode][odeint]") {
  // π(t) = π(0) + Γ ∫₀ᵗ f for a free body under a pure world torque: exact for any attitude
  // history. Outputs every 0.03 s, so the switch at 0.1 is not an output time: the drivers
  // must stop there on their own.
  const bool rectangular = GENERATE(false, true);
  CAPTURE(rectangular);
  const core::Model model = book_toss(rectangular);
  const std::vector<double> times = core::output_times(1.0, 0.03);
  const double rtol = 1e-12;
  const double momentum = model.angular_momentum_W(model.initial_state()).norm();
  for (const SolveFunction solve : {solve_ida, solve_cvode, solve_arkode, solve_odeint}) {
    const ReferenceRun run = solve(model, times, with_rtol(rtol));
    CAPTURE(run.solver);
    // N steps with local errors up to rtol·|π| each (the conservation bound of the solver
    // tests). Measured: IDA 6e-10, CVODE 2e-9, odeint 3e-13 against 2.8e-8, 7e-9, 7e-10. A
    // switch missed by δt would add |Γ|·δt = 0.28 δt.
    const double bound = static_cast<double>(run.stats.steps) * rtol * momentum;
    const double error = momentum_balance_error(model, run, rectangular);
    CAPTURE(error, bound);
    CHECK(error <= bound);
  }
}

TEST_CASE("book_toss_step: stopping at the switch matters", "[ida][cvode][arkode][odeint]") {
  // The same rectangular pulse, once known to the drivers (they stop and restart at 0.1) and
  // once hidden in the load (they step across the jump and rely on their error control).
  const core::Model planned = book_toss(true);
  const core::Model hidden = book_toss_hidden_switch();
  const std::vector<double> times = core::output_times(1.0, 0.03);
  const double rtol = 1e-12;

  // odeint: RKF7(8)'s error estimate (41/840 (k1 + k11 − k12 − k13) h) does not see a jump
  // between its stages and accepts a step across it: the momentum balance is off by 1e-5
  // instead of 3e-13 with the stop (bound N·rtol·|π| = 7e-10 as above).
  const ReferenceRun odeint_planned = solve_odeint(planned, times, with_rtol(rtol));
  const ReferenceRun odeint_hidden = solve_odeint(hidden, times, with_rtol(rtol));
  const double planned_error = momentum_balance_error(planned, odeint_planned, true);
  const double hidden_error = momentum_balance_error(hidden, odeint_hidden, true);
  CAPTURE(planned_error, hidden_error);
  CHECK(planned_error <= 1e-9);
  CHECK(hidden_error >= 1e-7);

  // IDA and CVODE: their error tests catch the jump, at the price of rejected steps while
  // they shrink the step onto it (measured: IDA 105 → 136, CVODE 4 → 22).
  for (const SolveFunction solve : {solve_ida, solve_cvode}) {
    const ReferenceRun with_stop = solve(planned, times, with_rtol(rtol));
    const ReferenceRun across = solve(hidden, times, with_rtol(rtol));
    CAPTURE(with_stop.solver, with_stop.stats.error_test_failures,
            across.stats.error_test_failures);
    CHECK(across.stats.error_test_failures > with_stop.stats.error_test_failures);
  }
}

TEST_CASE("a load that throws ends every solver with the time and the load's message",
          "[ida][cvode][arkode][odeint]") {
  std::vector<core::Body> bodies;
  bodies.emplace_back(testing::rigid_body("body", 1.0, {3.0, 4.0, 5.0}, {0.2, 0.3, 2.0}));
  testing::Elements elements;
  elements.push_back(std::make_unique<ThrowingTorque>());
  const core::Model model(std::move(bodies), std::move(elements));
  for (const SolveFunction solve : {solve_ida, solve_cvode, solve_arkode, solve_odeint}) {
    try {
      solve(model, core::output_times(1.0, 0.1), with_rtol(1e-10));
      FAIL("no SolverError");
    } catch (const core::SolverError& e) {
      CAPTURE(e.what());
      // The callbacks turn the exception into an unrecoverable flag (or odeint lets it
      // through); the driver reports the last time the solver reached, before the throw.
      CHECK(e.time() > 0.0);
      CHECK(e.time() <= 0.5);
      CHECK(std::string(e.what()).find("failed at t = ") != std::string::npos);
      CHECK(std::string(e.what()).find("torque table ends at t = 0.5") != std::string::npos);
    }
  }
}

}  // namespace flexref::reference
