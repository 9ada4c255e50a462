#include "core/time_profile.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/output_times.hpp"

namespace flexref::core {
namespace {

TEST_CASE("sin2 pulse is sin²(π t / d) inside, zero outside, branch by segment", "[core]") {
  const TimeProfile p = TimeProfile::sin2_pulse(0.0, 0.1);
  // At the peak sin² is stationary, so the argument's rounding enters squared: sin and the
  // square round once each, ≤ 2 ε < 1e-15. At π/4 the slope of sin² is 1: the argument's
  // rounding (≤ 2 ε of π/4) and two more add up to ~5 ε of 0.5 = 1.1e-15; 1e-14 bounds it.
  CHECK(p.value(0.05, 0.05) == Approx(1.0).epsilon(1e-15));
  CHECK(p.value(0.025, 0.025) == Approx(0.5).epsilon(1e-14));
  CHECK(p.value(0.2, 0.2) == 0.0);
  // At the end t = 0.1 both sides are (nearly) zero: sin²(π) ≈ 1.5e-32.
  CHECK(p.value(0.1, 0.095) < 1e-30);
  std::vector<double> d;
  p.append_discontinuities(d);
  CHECK(d == std::vector<double>{0.0, 0.1});
}

TEST_CASE("rectangular pulse gives left and right limits by segment", "[core]") {
  const TimeProfile p = TimeProfile::rectangular_pulse(0.0, 0.1);
  CHECK(p.value(0.1, 0.095) == 1.0);  // end of a step inside the pulse: left limit
  CHECK(p.value(0.1, 0.105) == 0.0);  // start of the next step: right limit
  CHECK(p.value(0.0, 0.005) == 1.0);
  CHECK(p.value(0.0, -0.005) == 0.0);
  CHECK_THROWS_AS(TimeProfile::rectangular_pulse(0.0, -1.0), std::invalid_argument);
}

TEST_CASE("output times land on the end time and reject bad grids", "[core]") {
  const auto t = output_times(10.0, 0.01);
  REQUIRE(t.size() == 1001);
  CHECK(t.back() == 10.0);
  CHECK(t[500] == 5.0);
  const auto u = output_times(1.0, 0.3);  // 0, 0.3, 0.6, 0.9, 1.0
  CHECK(u.size() == 5);
  CHECK(u.back() == 1.0);
  CHECK_THROWS_AS(output_times(0.0, 0.1), std::invalid_argument);
  CHECK_THROWS_AS(output_times(1.0, -0.1), std::invalid_argument);
  CHECK(is_multiple_of(0.1, 0.01 / 4));
  CHECK_FALSE(is_multiple_of(0.1, 0.03));
}

}  // namespace
}  // namespace flexref::core
