#include "studies/observed_order.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

namespace flexref::studies {
namespace {

// Explicit Euler and central differences on the harmonic oscillator x'' = −ω² x, x(0)=1,
// x'(0)=0, error |x_N − cos(ω T)| at T: textbook orders 1 and 2.
double euler_error(double h, double omega, double t_end) {
  double x = 1.0, v = 0.0;
  const long n = std::lround(t_end / h);
  for (long k = 0; k < n; ++k) {
    const double a = -omega * omega * x;
    x += h * v;
    v += h * a;
  }
  return std::abs(x - std::cos(omega * t_end));
}

double central_difference_error(double h, double omega, double t_end) {
  double x = 1.0, v = 0.0, a = -omega * omega * x;
  const long n = std::lround(t_end / h);
  for (long k = 0; k < n; ++k) {
    x += h * v + 0.5 * h * h * a;  // x_{n+1} = x_n + h v_n + ½h² a_n
    const double a_next = -omega * omega * x;
    v += 0.5 * h * (a + a_next);  // v_{n+1} = v_n + ½h (a_n + a_{n+1})
    a = a_next;
  }
  return std::abs(x - std::cos(omega * t_end));
}

TEST_CASE("pairwise and least-squares orders recover a synthetic sequence", "[studies]") {
  // e = C h^p exactly: both estimators return p to round-off (log of exact powers of two).
  for (double p : {1.0, 2.0, 3.5}) {
    std::vector<double> h, e;
    for (int k = 0; k < 6; ++k) {
      h.push_back(0.1 / std::ldexp(1.0, k));
      e.push_back(3.0 * std::pow(h.back(), p));
    }
    for (double pi : pairwise_orders(h, e)) CHECK(pi == Approx(p).epsilon(1e-12));
    CHECK(least_squares_order(h, e, std::vector<bool>(6, true)) == Approx(p).epsilon(1e-12));
  }
}

TEST_CASE("least squares skips unused and unusable levels", "[studies]") {
  const std::vector<double> h{0.4, 0.2, 0.1, 0.05};
  const std::vector<double> e{1.0, 0.25, 0.0625, 0.0};  // order 2, last level zero
  CHECK(std::isnan(pairwise_orders(h, e)[2]));
  CHECK(least_squares_order(h, e, {true, true, true, true}) == Approx(2.0).epsilon(1e-12));
  CHECK(std::isnan(least_squares_order(h, e, {true, false, false, false})));
}

TEST_CASE("observed orders of textbook schemes on a harmonic oscillator", "[studies]") {
  // ω = 2, T = 5 (several periods), h from 1e-3: asymptotic range for both schemes
  // (ωh ≤ 2e-3); the next term of the error expansion changes the ratio by O(ωh) ≈ 1e-3…1e-2.
  std::vector<double> h, e_euler, e_cd;
  for (int k = 0; k < 4; ++k) {
    h.push_back(1e-3 / std::ldexp(1.0, k));
    e_euler.push_back(euler_error(h.back(), 2.0, 5.0));
    e_cd.push_back(central_difference_error(h.back(), 2.0, 5.0));
  }
  const std::vector<bool> all(4, true);
  CHECK(least_squares_order(h, e_euler, all) == Approx(1.0).margin(0.05));
  CHECK(least_squares_order(h, e_cd, all) == Approx(2.0).margin(0.05));
}

TEST_CASE("the distance order recovers p from solutions with a floor, at any step ratios",
          "[studies]") {
  // u(h) = u* + C h^p with u* = 0.7 (a limit the distances never see) and steps of unequal
  // ratios (1.5, 2, 1.25, 3): d = C (h_c^p − h_f^p) exactly, so the fit's residual vanishes at
  // p and the golden-section search stops within 1e-10 of it; 1e-8 covers the round-off of the
  // logarithms near the minimum (the residual is flat there: its square root moves by ~1e-8).
  const std::vector<double> h{0.9, 0.6, 0.3, 0.24, 0.08};
  for (const double p : {0.8, 1.0, 2.0, 3.0}) {
    std::vector<LevelDistance> pairs;
    for (std::size_t i = 0; i + 1 < h.size(); ++i) {
      const double coarse = 0.7 + 2.0 * std::pow(h[i], p);
      const double fine = 0.7 + 2.0 * std::pow(h[i + 1], p);
      pairs.push_back({h[i], h[i + 1], std::abs(coarse - fine)});
    }
    CHECK(distance_order(pairs) == Approx(p).margin(1e-8));
  }
}

TEST_CASE("the distance order of halving steps is the slope, too few pairs give NaN", "[studies]") {
  // Halving: d_i = C h_i^p (1 − 2^−p), the slope of log d against log h (to round-off).
  std::vector<LevelDistance> pairs;
  for (int k = 0; k < 3; ++k) {
    const double hc = 1.0 / std::ldexp(1.0, k);
    pairs.push_back({hc, 0.5 * hc, 5.0 * hc * hc * 0.75});
  }
  CHECK(distance_order(pairs) == Approx(2.0).margin(1e-8));  // as above
  CHECK(std::isnan(distance_order({pairs[0]})));
  CHECK(std::isnan(distance_order({pairs[0], {0.25, 0.125, 0.0}})));  // a zero distance
  // Distances that do not decrease fit no order in [0.05, 10].
  CHECK(std::isnan(distance_order({{1.0, 0.5, 1.0}, {0.5, 0.25, 2.0}, {0.25, 0.125, 4.0}})));
}

}  // namespace
}  // namespace flexref::studies
