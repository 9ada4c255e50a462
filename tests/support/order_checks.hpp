#pragma once
/// \file order_checks.hpp
/// The two-sided order test of docs/design/style.md "Tests" (after Drake's ErrEstOrder): the
/// errors of one scheme at steps h, h/2, h/4, … against a reference must fall by 2^p per halving,
/// within a window narrow enough that order p − 1 or p + 1 fails.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

namespace flexref::testing {

/// Checks that each ratio e(h)/e(h/2) of `errors` (steps halving) lies in [2^(p−0.2), 2^(p+0.3)]
/// and that the reference's own error is at most 1 % of the smallest error it measures.
///
/// The window: an order-p error is C h^p (1 + c h + …), so a ratio is 2^p (1 + c h/2 + …); the
/// window lets that correction move a ratio by −13 % … +23 % (the schemes' errors converge to
/// their leading term from above or below) and excludes the ratios 2^(p−1) and 2^(p+1) of the
/// neighbouring orders by a factor 2^0.7 or more. The reference at ≤ 1 % of the smallest error
/// changes a ratio by at most a factor 1.01/0.99 ≈ 2^0.03, inside the window's margins.
inline void check_two_sided_order(const std::vector<double>& errors, double p,
                                  double reference_error) {
  REQUIRE(errors.size() >= 2);
  CHECK(reference_error <= 1e-2 * errors.back());
  for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
    const double ratio = errors[k] / errors[k + 1];
    INFO("e = " << errors[k] << " -> " << errors[k + 1] << ", ratio " << ratio
                << ", observed order " << std::log2(ratio) << ", expected " << p);
    CHECK(ratio >= std::pow(2.0, p - 0.2));
    CHECK(ratio <= std::pow(2.0, p + 0.3));
  }
}

}  // namespace flexref::testing
