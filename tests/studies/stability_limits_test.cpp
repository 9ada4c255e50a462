#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "lie/rotational_stability.hpp"
#include "lie/stepper.hpp"
#include "studies/stability.hpp"

namespace flexref::studies {
namespace {

TEST_CASE("the rotational stability limits run warns with are what the stability study measures",
          "[studies][stability]") {
  // The measurement lie/rotational_stability.hpp describes: free_spin's body, the study's
  // default criterion (1000 steps, ±50 % energy and momentum), bisection to 1e-3, at two spin
  // rates (h_max·|W| is the same at every rate).
  StabilityOptions options;
  options.values = {1.0, 100.0};
  options.schemes = lie::builtin_scheme_names();
  options.degenerate = false;
  const StabilityResult result = run_stability(options);
  REQUIRE(result.sweep.size() == 2 * options.schemes.size());
  for (const StabilityPoint& p : result.sweep) {
    INFO(p.scheme << " at |W| = " << p.spin << ": h_max|W| = " << p.h_max * p.spin);
    const double limit = lie::rotational_stability_limit(p.scheme);
    REQUIRE(limit > 0.0);
    const double measured = p.h_max * p.spin;
    // The limit is the measured value rounded down to three digits: at most the measurement
    // (whose h_stable lies up to the bisection's 1e-3 below the true limit) and less than one
    // unit of its third digit below it.
    const double unit = std::pow(10.0, std::floor(std::log10(limit)) - 2.0);
    CHECK(limit <= measured * (1.0 + 1e-3));
    CHECK(measured < limit + unit);
  }
  CHECK(lie::rotational_stability_limit("a user's method") == 0.0);
}

}  // namespace
}  // namespace flexref::studies
