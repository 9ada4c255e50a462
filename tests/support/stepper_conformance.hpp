#pragma once
/// \file stepper_conformance.hpp
/// The conformance suite of a lie::Stepper, instantiated for any registered method in one line
/// (after Drake's generic_integrator_test.h, which every Drake integrator instantiates):
///
///     FLEXREF_STEPPER_CONFORMANCE_TESTS("c2")
///
/// registers Catch2 test cases that check, for the method of that name in the registry
/// (lie/method_registry.hpp):
///   - the registry entry and the stepper agree (name, claimed order, evaluations ≥ 1);
///   - two-sided order on an exact non-commuting flow (regular precession): e(h)/e(h/2) in
///     [2^(p−0.2), 2^(p+0.3)] for the claimed order p (Drake's ErrEstOrder check), and the
///     global error below the consistency bound h^p |W|^(p+1) T;
///   - failure semantics: a step that meets a NaN torque fails, says "non-finite" and the time,
///     and leaves state and time untouched (a retry fails the same way);
///   - run_scheme turns that failure into a core::SolverError with the time and step;
///   - bodies of one model advance as each would alone;
///   - Euler parameters stay unit to 2ε.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "lie/method_registry.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::testing {

inline bool same_state(const core::State& a, const core::State& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].p_WBr != b[i].p_WBr || a[i].theta_WB != b[i].theta_WB || a[i].v_WBr != b[i].v_WBr ||
        a[i].w_WB_B != b[i].w_WB_B) {
      return false;
    }
  }
  return true;
}

inline void check_registry_entry(const std::string& name) {
  const lie::MethodInfo* method = lie::find_method(name);
  REQUIRE(method != nullptr);
  const core::Model model = free_spin();
  const auto stepper = lie::make_stepper(name, model, {});
  CHECK(stepper->name() == name);
  CHECK(stepper->order() == method->claimed_order);
  CHECK(stepper->force_evaluations_per_step() >= 1.0);
}

inline void check_order_on_regular_precession(const std::string& name) {
  // Torque-free symmetric body, J = diag(2, 2, 3), W0 = (0.6, −0.4, 1.5), non-identity
  // attitude, uniform translation: W rotates in the body at λ = 0.75 rad/s, so the flow is not
  // solved exactly by every consistent method (as a constant W would be).
  const RegularPrecession exact;
  const core::Model model = exact.model();
  const std::vector<double> times = core::output_times(10.0, 0.5);
  core::Trajectory reference;
  reference.times = times;
  for (double t : times) reference.states.push_back({exact.state(t)});
  const int p = lie::find_method(name)->claimed_order;
  std::vector<double> errors;
  const std::vector<double> steps{0.05, 0.025, 0.0125};
  for (double h : steps) {
    const auto stepper = lie::make_stepper(name, model, {});
    errors.push_back(
        trajectory_error(model, lie::run_scheme(model, *stepper, h, times), reference));
  }
  // Two-sided order check (Drake ErrEstOrder): e(h)/e(h/2) in [2^(p−0.2), 2^(p+0.3)] (h|W| ≤
  // 0.08: the asymptotic range; measured 4.00 for C1, C2, NMB and 2.00 for Lie–Euler).
  for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
    INFO(name << " h-level " << k << ": e = " << errors[k] << " -> " << errors[k + 1]);
    CHECK(errors[k] / errors[k + 1] >= std::pow(2.0, p - 0.2));
    CHECK(errors[k] / errors[k + 1] <= std::pow(2.0, p + 0.3));
  }
  // Consistency: the global error of an order-p method is ≤ C h^p |W|^(p+1) T with C = O(1):
  // h = 0.0125, |W| = 1.66, T = 10 (p = 2: 7.2e-3, measured 1.3e-4 c1, 6.4e-4 c2, 6.4e-5 nmb;
  // p = 1: 0.34).
  const double w = exact.w0_B.norm();
  INFO(name << ": e = " << errors.back());
  CHECK(errors.back() <= std::pow(steps.back(), p) * std::pow(w, p + 1) * 10.0);
}

inline void check_failed_step_leaves_state(const std::string& name) {
  // The torque becomes NaN for steps inside (0.5, ∞): the sixth step of h = 0.1 fails.
  const core::Model model = free_spin_failing_after(0.5);
  const auto stepper = lie::make_stepper(name, model, {});
  stepper->initialize(0.0, model.initial_state());
  for (int n = 0; n < 5; ++n) REQUIRE(stepper->step(0.1).ok);
  const core::State before = stepper->state();
  const double t_before = stepper->time();
  const lie::StepStatus status = stepper->step(0.1);
  CHECK_FALSE(status.ok);
  INFO(status.message);
  CHECK(status.message.find("non-finite") != std::string::npos);
  CHECK(status.message.find("0.5") != std::string::npos);
  CHECK(same_state(stepper->state(), before));
  CHECK(stepper->time() == t_before);
  // A retry fails the same way: nothing was half-committed.
  CHECK_FALSE(stepper->step(0.1).ok);
  CHECK(same_state(stepper->state(), before));
}

inline void check_run_scheme_reports_failure(const std::string& name) {
  const core::Model model = free_spin_failing_after(0.5);
  const auto stepper = lie::make_stepper(name, model, {});
  try {
    lie::run_scheme(model, *stepper, 0.1, core::output_times(1.0, 0.1));
    FAIL("no SolverError");
  } catch (const core::SolverError& e) {
    CHECK(e.solver() == name);
    CHECK(e.step() == 5);
    // t_5 = 5 × 0.1 (run_scheme multiplies, never accumulates): one rounding of 0.5, ≤ 5.6e-17.
    CHECK(e.time() == Approx(0.5).margin(1e-15));
  }
}

inline void check_bodies_independent(const std::string& name) {
  const core::Model both = book_and_top();
  const core::Model book = book_toss();
  const core::Model top = heavy_top();
  const std::vector<double> times = core::output_times(0.2, 0.1);
  const double h = 1e-3;
  const auto s_both = lie::make_stepper(name, both, {});
  const auto s_book = lie::make_stepper(name, book, {});
  const auto s_top = lie::make_stepper(name, top, {});
  const core::Trajectory r_both = lie::run_scheme(both, *s_both, h, times);
  const core::Trajectory r_book = lie::run_scheme(book, *s_book, h, times);
  const core::Trajectory r_top = lie::run_scheme(top, *s_top, h, times);
  // The bodies are uncoupled, so explicit schemes do the same arithmetic (identical results);
  // an implicit scheme's block Newton iterates until both bodies converge, so the book may
  // take one more round-off-sized correction per step: ≤ 200 steps × 4ε ≈ 2e-13 relative,
  // checked at 1e-12 of the state's scale (|W| ≤ 150, |θ| = 1).
  for (std::size_t k = 0; k < times.size(); ++k) {
    const core::BodyState& b = r_both.states[k][0];
    const core::BodyState& t = r_both.states[k][1];
    CHECK((b.theta_WB - r_book.states[k][0].theta_WB).norm() <= 1e-12);
    CHECK((b.w_WB_B - r_book.states[k][0].w_WB_B).norm() <= 1e-12 * 10.0);
    CHECK((b.p_WBr - r_book.states[k][0].p_WBr).norm() <= 1e-12);
    CHECK((t.theta_WB - r_top.states[k][0].theta_WB).norm() <= 1e-12);
    CHECK((t.w_WB_B - r_top.states[k][0].w_WB_B).norm() <= 1e-12 * 150.0);
    CHECK(t.p_WBr == r_top.states[k][0].p_WBr);  // the pivot does not move
  }
}

inline void check_unit_euler_parameters(const std::string& name) {
  // Renormalized after every composition: |θ| − 1 is a single rounding, ≤ 2ε.
  const core::Model model = book_toss();
  const auto stepper = lie::make_stepper(name, model, {});
  stepper->initialize(0.0, model.initial_state());
  double drift = 0.0;
  for (int n = 0; n < 1000; ++n) {
    REQUIRE(stepper->step(1e-3).ok);
    drift = std::max(drift, std::abs(stepper->state()[0].theta_WB.norm() - 1.0));
  }
  CHECK(drift <= 2.0 * std::numeric_limits<double>::epsilon());
}

}  // namespace flexref::testing

/// The conformance test cases for the registered method NAME (a string literal).
#define FLEXREF_STEPPER_CONFORMANCE_TESTS(NAME)                                                 \
  TEST_CASE("stepper " NAME ": registry entry, name and claimed order", "[lie][conformance]") { \
    flexref::testing::check_registry_entry(NAME);                                               \
  }                                                                                             \
  TEST_CASE("stepper " NAME ": converges to the exact regular precession at its claimed order", \
            "[lie][conformance]") {                                                             \
    flexref::testing::check_order_on_regular_precession(NAME);                                  \
  }                                                                                             \
  TEST_CASE("stepper " NAME ": a failed step leaves state and time untouched and says why",     \
            "[lie][conformance]") {                                                             \
    flexref::testing::check_failed_step_leaves_state(NAME);                                     \
  }                                                                                             \
  TEST_CASE("stepper " NAME ": run_scheme reports a failed step with time and step",            \
            "[lie][conformance]") {                                                             \
    flexref::testing::check_run_scheme_reports_failure(NAME);                                   \
  }                                                                                             \
  TEST_CASE("stepper " NAME ": the bodies of one model advance as each would alone",            \
            "[lie][conformance]") {                                                             \
    flexref::testing::check_bodies_independent(NAME);                                           \
  }                                                                                             \
  TEST_CASE("stepper " NAME ": Euler parameters stay unit", "[lie][conformance]") {             \
    flexref::testing::check_unit_euler_parameters(NAME);                                        \
  }
