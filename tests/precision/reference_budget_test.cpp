/// \file reference_budget_test.cpp
/// The cost guard's projection (precision/reference_budget.hpp) on made-up clocks, where every
/// branch is reachable: no budget, the 1 % gate, t at t0, the projection just under and just
/// over, and the earlier runs' time and the factor entering the sum.
#include "precision/reference_budget.hpp"

#include <catch2/catch.hpp>
#include <string>

namespace flexref::precision {
namespace {

/// The projection check_budget threw, or −1 when it returned.
double thrown_projection(const Budget& budget, double elapsed, double t) {
  try {
    check_budget(budget, elapsed, 1.0, t, 11.0, Precision::kQuad);
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
  CHECK(thrown_projection(budget, 10.1, 2.0) == Approx(101.0));
  // The earlier runs' 30 s and a factor 3: 30 + 3 × 2.5 × 10 = 105 s, over; 2.3 s: 99 s, not.
  CHECK(thrown_projection({100.0, 30.0, 3.0}, 2.5, 2.0) == Approx(105.0));
  CHECK(thrown_projection({100.0, 30.0, 3.0}, 2.3, 2.0) == -1.0);
  // The whole span done: the projection is the time spent, never less.
  CHECK(thrown_projection(budget, 100.5, 11.0) == Approx(100.5));
}

TEST_CASE("the budget projects nothing without a budget, at t0 or before 1 % of it",
          "[precision]") {
  // Each of these would project far over (elapsed × 1e4 or more) if it were not gated.
  CHECK(thrown_projection({0.0, 0.0, 3.0}, 50.0, 1.001) == -1.0);
  CHECK(thrown_projection({100.0, 0.0, 1.0}, 50.0, 1.0) == -1.0);
  CHECK(thrown_projection({100.0, 0.0, 1.0}, 0.99, 1.001) == -1.0);
  CHECK(thrown_projection({100.0, 0.0, 1.0}, 1.01, 1.001) == Approx(1.01e4));
}

TEST_CASE("the budget's message names the precision, the projection and the budget",
          "[precision]") {
  try {
    check_budget({3600.0, 0.0, 3.0}, 60.0, 0.0, 0.1, 10.0, Precision::kQuad);
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
