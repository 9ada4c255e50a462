/// \file reference_budget_test.cpp
/// The cost guard's projection (precision/reference_budget.hpp) on made-up clocks, where every
/// branch is reachable: no budget, the 1 % gate, t at t0, the projection just under and just
/// over, the earlier runs' time and the factor entering the sum, and the recent-rate window
/// (rising and falling cost, checks at one simulated time, the end reached).
#include "precision/reference_budget.hpp"

#include <catch2/catch.hpp>
#include <string>

namespace flexref::precision {
namespace {

/// The projection check_budget threw, or −1 when it returned.
double thrown_projection(const Budget& budget, double elapsed, double t) {
  try {
    RateWindow window(1.0);
    check_budget(budget, window, elapsed, t, 11.0, Precision::kQuad);
  } catch (const BudgetExceeded& e) {
    CHECK(e.budget_seconds() == budget.seconds);
    CHECK(e.reached_time() == t);
    return e.projected_seconds();
  }
  return -1.0;
}

TEST_CASE("the budget projects spent + factor x elapsed x span / reached", "[precision]") {
  // A run over t in [1, 11] s: at t = 2 s it has covered 1/10 of its span.
  const Budget budget{100.0, 0.0, 1.0};
  // 9.9 s elapsed: projection 99 s, under 100 s. 10.1 s: 101 s, over.
  CHECK(thrown_projection(budget, 9.9, 2.0) == -1.0);
  // Tolerance: every projection below is a handful of products and quotients of the numbers
  // written (no iteration): a few roundings of O(1)-relative operations, each ≤ 2^-53 ≈ 1.1e-16:
  // 1e-14 leaves a factor ~10 over them.
  CHECK(thrown_projection(budget, 10.1, 2.0) == Approx(101.0).epsilon(1e-14));
  // The earlier runs' 30 s and a factor 3: 30 + 3 × 2.5 × 10 = 105 s, over; 2.3 s: 99 s, not.
  CHECK(thrown_projection({100.0, 30.0, 3.0}, 2.5, 2.0) == Approx(105.0).epsilon(1e-14));
  CHECK(thrown_projection({100.0, 30.0, 3.0}, 2.3, 2.0) == -1.0);
  // The whole span done: the projection is the time spent, never less.
  CHECK(thrown_projection(budget, 100.5, 11.0) == Approx(100.5).epsilon(1e-14));
}

TEST_CASE("the budget projects nothing without a budget, at t0 or before 1 % of it",
          "[precision]") {
  // Each of these would project far over (elapsed × 1e4 or more) if it were not gated.
  CHECK(thrown_projection({0.0, 0.0, 3.0}, 50.0, 1.001) == -1.0);
  CHECK(thrown_projection({100.0, 0.0, 1.0}, 50.0, 1.0) == -1.0);
  CHECK(thrown_projection({100.0, 0.0, 1.0}, 0.99, 1.001) == -1.0);
  // Tolerance: the share done (1.001 − 1)/span cancels three digits, so its rounding (≤ 2^-53
  // of 1.001) is ~1.1e-13 relative to 1e-3 (measured 1.1e-13): 1e-11 leaves a factor ~100.
  CHECK(thrown_projection({100.0, 0.0, 1.0}, 1.01, 1.001) == Approx(1.01e4).epsilon(1e-11));
}

TEST_CASE("the budget projects the time left at the rate of the last half of the run",
          "[precision]") {
  // A run over t in [0, 10] s. 1 s for its first 0.1 s: 10 s per simulated second, 100 s in
  // all. At 2 s and t = 0.2 the elapsed time has doubled: the window starts at (1 s, 0.1).
  RateWindow rising(0.0);
  CHECK(rising.projected_run(1.0, 0.1, 10.0) == Approx(100.0).epsilon(1e-14));
  CHECK(rising.projected_run(2.0, 0.2, 10.0) == Approx(2.0 + 9.8 * 10.0).epsilon(1e-14));
  // Then 3 s for the next 0.05 s (the load excites the top modes): 60 s per second now,
  // 5 + 9.75 × 60 = 590 s, where the average rate (20 s per second) would project 200 s.
  CHECK(rising.projected_run(5.0, 0.25, 10.0) == Approx(590.0).epsilon(1e-14));
  // Front-loaded: 1 s for the first 0.1, 1 s for the next 0.4: 2 + 9.5 × 2.5 = 25.75 s
  // (the average would say 40 s).
  RateWindow falling(0.0);
  CHECK(falling.projected_run(1.0, 0.1, 10.0) == Approx(100.0).epsilon(1e-14));
  CHECK(falling.projected_run(2.0, 0.5, 10.0) == Approx(25.75).epsilon(1e-14));
  // The window keeps at least the last half: at 3 s (< 2 × 2 s) the mark stays at (1 s, 0.1).
  CHECK(falling.projected_run(3.0, 0.9, 10.0) == Approx(3.0 + 9.1 * 2.0 / 0.8).epsilon(1e-14));
  // No simulated time since the mark (checks during event location at one t): the average.
  RateWindow stuck(0.0);
  CHECK(stuck.projected_run(1.0, 0.1, 10.0) == Approx(100.0).epsilon(1e-14));
  CHECK(stuck.projected_run(2.0, 0.1, 10.0) == Approx(2.0 + 9.9 * 20.0).epsilon(1e-14));
  // The end reached: the time spent, never less.
  CHECK(stuck.projected_run(4.5, 10.0, 10.0) == Approx(4.5).epsilon(1e-14));
}

TEST_CASE("a run is stopped at the first check whose recent rate projects over the budget",
          "[precision]") {
  // Budget 300 s, factor 1, t in [0, 10]: at (5 s, 0.5) the average rate projects 100 s; the
  // cost then rises to 40 s per simulated second, and at (10 s, 0.625) the window from
  // (5 s, 0.5) projects 10 + 9.375 × 40 = 385 s (the average: 160 s, under the budget).
  const Budget budget{300.0, 0.0, 1.0};
  RateWindow window(0.0);
  CHECK_NOTHROW(check_budget(budget, window, 5.0, 0.5, 10.0, Precision::kQuad));
  RateWindow average(0.0);  // one sample: the average rate
  CHECK_NOTHROW(check_budget(budget, average, 10.0, 0.625, 10.0, Precision::kQuad));
  try {
    check_budget(budget, window, 10.0, 0.625, 10.0, Precision::kQuad);
    FAIL("projected 385 s against 300 s and did not throw");
  } catch (const BudgetExceeded& e) {
    // Tolerance: a handful of products and quotients of the numbers written: a few roundings of
    // O(1)-relative operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
    CHECK(e.projected_seconds() == Approx(385.0).epsilon(1e-14));
    CHECK(e.reached_time() == 0.625);
  }
}

TEST_CASE("the budget's message names the precision, the projection and the budget",
          "[precision]") {
  try {
    RateWindow window(0.0);
    check_budget({3600.0, 0.0, 3.0}, window, 60.0, 0.1, 10.0, Precision::kQuad);
    FAIL("projected 1.8e4 s against 3600 s and did not throw");
  } catch (const BudgetExceeded& e) {
    const std::string what = e.what();
    CHECK(what.find("quad-precision reference") != std::string::npos);
    CHECK(what.find("1.8e+04 s of wall time (at t = 0.1 s after 60 s)") != std::string::npos);
    CHECK(what.find("over its budget of 3600 s") != std::string::npos);
  }
}

}  // namespace
}  // namespace flexref::precision
