/// The conformance suite every rotation scheme joins by being listed in scheme_names() (Drake
/// generic_integrator_test style): consistency with an exact non-commuting flow, failure
/// semantics, non-finite detection, and multi-body stepping.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::lie {
namespace {

bool same_state(const core::State& a, const core::State& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].p_WBr != b[i].p_WBr || a[i].theta_WB != b[i].theta_WB || a[i].v_WBr != b[i].v_WBr ||
        a[i].w_WB_B != b[i].w_WB_B) {
      return false;
    }
  }
  return true;
}

TEST_CASE("make_stepper builds every scheme of scheme_names and rejects others",
          "[lie][conformance]") {
  const core::Model model = testing::free_spin();
  CHECK(scheme_names() == std::vector<std::string>{"c1", "c2", "nmb"});
  for (const std::string& name : scheme_names()) {
    const auto stepper = make_stepper(name, model);
    CHECK(stepper->name() == name);
    CHECK(stepper->order() == 2);  // Simo–Wong and Krysl–Endres claim second order
    CHECK(stepper->force_evaluations_per_step() >= 1.0);
  }
  CHECK_THROWS_AS(make_stepper("rk4", model), std::invalid_argument);
}

TEST_CASE("every scheme converges to the exact regular precession at order 2",
          "[lie][conformance]") {
  // Torque-free symmetric body, J = diag(2, 2, 3), W0 = (0.6, −0.4, 1.5), non-identity
  // attitude, uniform translation: W rotates in the body at λ = 0.75 rad/s, so the flow is not
  // solved exactly by every consistent method (as a constant W would be).
  const testing::RegularPrecession exact;
  const core::Model model = exact.model();
  const std::vector<double> times = core::output_times(10.0, 0.5);
  core::Trajectory reference;
  reference.times = times;
  for (double t : times) reference.states.push_back({exact.state(t)});

  for (const std::string& name : scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      std::vector<double> errors;
      for (double h : {0.05, 0.025, 0.0125}) {
        const auto stepper = make_stepper(name, model);
        errors.push_back(
            testing::trajectory_error(model, run_scheme(model, *stepper, h, times), reference));
      }
      // Two-sided order check (Drake ErrEstOrder): for p = 2 the ratio e(h)/e(h/2) lies in
      // [2^(p−0.2), 2^(p+0.3)]. Measured 4.00 for all three (h|W| ≤ 0.08, asymptotic range).
      for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
        INFO("h-level " << k << ": e = " << errors[k] << " -> " << errors[k + 1]);
        CHECK(errors[k] / errors[k + 1] >= std::pow(2.0, 1.8));
        CHECK(errors[k] / errors[k + 1] <= std::pow(2.0, 2.3));
      }
      // Consistency: the global error of a second-order method is ≤ C h²|W|³ T with C = O(1);
      // h = 0.0125, |W| = 1.66, T = 10: h²|W|³T = 7.2e-3 (measured 1.3e-4 c1, 6.4e-4 c2,
      // 6.4e-5 nmb).
      CHECK(errors.back() <= 7.2e-3);
    }
  }
}

TEST_CASE("a failed step leaves the state and the time untouched and says why",
          "[lie][conformance]") {
  // The torque becomes NaN for steps inside (0.5, ∞): the sixth step of h = 0.1 fails.
  const core::Model model = testing::free_spin_failing_after(0.5);
  for (const std::string& name : scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      const auto stepper = make_stepper(name, model);
      stepper->initialize(0.0, model.initial_state());
      for (int n = 0; n < 5; ++n) REQUIRE(stepper->step(0.1).ok);
      const core::State before = stepper->state();
      const double t_before = stepper->time();
      const StepStatus status = stepper->step(0.1);
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
  }
}

TEST_CASE("run_scheme turns a non-finite step into a SolverError with time and step",
          "[lie][conformance]") {
  const core::Model model = testing::free_spin_failing_after(0.5);
  for (const std::string& name : scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      const auto stepper = make_stepper(name, model);
      try {
        run_scheme(model, *stepper, 0.1, core::output_times(1.0, 0.1));
        FAIL("no SolverError");
      } catch (const core::SolverError& e) {
        CHECK(e.solver() == name);
        CHECK(e.step() == 5);
        CHECK(e.time() == Approx(0.5).margin(1e-15));
      }
    }
  }
}

TEST_CASE("all bodies of a model advance at once as each would alone", "[lie][conformance]") {
  const core::Model both = testing::book_and_top();
  const core::Model book = testing::book_toss();
  const core::Model top = testing::heavy_top();
  const std::vector<double> times = core::output_times(0.2, 0.1);
  for (const std::string& name : scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      const double h = 1e-3;
      const auto s_both = make_stepper(name, both);
      const auto s_book = make_stepper(name, book);
      const auto s_top = make_stepper(name, top);
      const core::Trajectory r_both = run_scheme(both, *s_both, h, times);
      const core::Trajectory r_book = run_scheme(book, *s_book, h, times);
      const core::Trajectory r_top = run_scheme(top, *s_top, h, times);
      // The bodies are uncoupled, so the explicit schemes do the same arithmetic (identical
      // results); C1's block Newton iterates until both bodies converge, so the book may take
      // one more round-off-sized correction per step: ≤ 200 steps × 4ε ≈ 2e-13 relative,
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
  }
}

TEST_CASE("every scheme keeps the Euler parameters unit", "[lie][conformance]") {
  // Renormalized after every composition: |θ| − 1 is a single rounding, ≤ 2ε.
  const core::Model model = testing::book_toss();
  for (const std::string& name : scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      const auto stepper = make_stepper(name, model);
      stepper->initialize(0.0, model.initial_state());
      double drift = 0.0;
      for (int n = 0; n < 1000; ++n) {
        REQUIRE(stepper->step(1e-3).ok);
        drift = std::max(drift, std::abs(stepper->state()[0].theta_WB.norm() - 1.0));
      }
      CHECK(drift <= 2.0 * std::numeric_limits<double>::epsilon());
    }
  }
}

}  // namespace
}  // namespace flexref::lie
