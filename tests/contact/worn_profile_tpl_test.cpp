/// The worn profile around a gap support (contact/worn_profile_tpl.hpp): the periodic
/// Catmull–Rom spline through the sector centres and the hat weights of the deposit.
#include "contact/worn_profile_tpl.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace flexref::contact {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> random_depths(int sectors, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 2e-4);
  std::vector<double> h(static_cast<std::size_t>(sectors));
  for (double& x : h) x = u(rng);
  return h;
}

std::array<double, 2> profile_at(double phi, const std::vector<double>& h) {
  return worn_profile_at<double>(worn_profile_weights<double>(phi, static_cast<int>(h.size())), h);
}

}  // namespace

TEST_CASE("worn profile: the spline passes through the sector depths at their centres") {
  for (const int sectors : {1, 2, 3, 12, 36}) {
    const std::vector<double> h = random_depths(sectors, 7u + static_cast<unsigned>(sectors));
    for (int j = 0; j < sectors; ++j) {
      const double centre = (j + 0.5) * 2.0 * kPi / sectors;
      // At a centre t = 0: b = (0, 1, 0, 0) exactly; 1e-15 m is the round-off of φ/Δ − ½.
      INFO("sectors " << sectors << ", sector " << j);
      CHECK(profile_at(centre, h)[0] == Approx(h[static_cast<std::size_t>(j)]).margin(1e-15));
      // Periodic: the same angle a turn later or earlier.
      CHECK(profile_at(centre + 2.0 * kPi, h)[0] ==
            Approx(h[static_cast<std::size_t>(j)]).margin(1e-15));
      CHECK(profile_at(centre - 4.0 * kPi, h)[0] ==
            Approx(h[static_cast<std::size_t>(j)]).margin(1e-15));
    }
  }
}

TEST_CASE(
    "worn profile: a uniform depth is uniform, flat, and its slope is the value's derivative") {
  const std::vector<double> uniform(12, 1.5e-4);
  for (double phi = -3.0; phi < 7.0; phi += 0.37) {
    const std::array<double, 2> p = profile_at(phi, uniform);
    // Σ b_m = 1 and Σ db_m/dφ = 0 for every t: exact to the round-off of four products.
    CHECK(p[0] == Approx(1.5e-4).epsilon(1e-14));
    CHECK(std::abs(p[1]) < 1e-18);
  }
  const std::vector<double> h = random_depths(36, 3u);
  for (double phi = -1.0; phi < 6.5; phi += 0.113) {
    // Central differences of h(φ): the spline is a cubic in φ within a segment, so the
    // difference's truncation error is δ² |h'''|/6 ≤ 1e-14 × 2e-4 × (36/2π)³ / 6 ≈ 7e-17 m/rad,
    // and its round-off ε |h| / δ ≈ 4e-14 m/rad at δ = 1e-7 rad, against slopes of ~1e-3 m/rad:
    // a margin of 1e-12 m/rad (segments whose boundary falls inside ±δ are skipped below).
    const double delta = 1e-7;
    const WornProfileWeightsTpl<double> w = worn_profile_weights<double>(phi, 36);
    if (w.sector != worn_profile_weights<double>(phi + delta, 36).sector ||
        w.sector != worn_profile_weights<double>(phi - delta, 36).sector) {
      continue;
    }
    const double fd = (profile_at(phi + delta, h)[0] - profile_at(phi - delta, h)[0]) / (2 * delta);
    CHECK(profile_at(phi, h)[1] == Approx(fd).margin(1e-12));
  }
}

TEST_CASE("worn profile: value and slope are continuous where the segment changes (C1)") {
  const std::vector<double> h = random_depths(12, 11u);
  for (int j = 0; j < 12; ++j) {
    const double centre = (j + 0.5) * 2.0 * kPi / 12;
    const std::array<double, 2> left = profile_at(centre - 1e-12, h);
    const std::array<double, 2> right = profile_at(centre + 1e-12, h);
    // Across a centre the four sectors change; C¹: both sides agree to the change over 2e-12
    // rad (slopes ≲ 1e-2 m/rad, curvatures ≲ 1 m/rad²): 1e-13.
    CHECK(left[0] == Approx(right[0]).margin(1e-13));
    CHECK(left[1] == Approx(right[1]).margin(1e-10));
  }
}

TEST_CASE(
    "worn profile: the deposit's hat weights are >= 0, sum to 1 and go to the bracketing centres") {
  for (const int sectors : {1, 2, 7, 36}) {
    for (double phi = -5.0; phi < 8.0; phi += 0.29) {
      const WornProfileWeightsTpl<double> w = worn_profile_weights<double>(phi, sectors);
      CHECK(w.deposit[0] >= 0.0);
      CHECK(w.deposit[1] >= 0.0);
      // (1 − t) + t: one rounding in 1 − t and one in the sum, each ≤ ε/2 ≈ 1.1e-16 relative to
      // 1; 1e-15 is 4.5 times their sum.
      CHECK(w.deposit[0] + w.deposit[1] == Approx(1.0).epsilon(1e-15));
      // The deposit's sectors are the spline's middle two, whose centres bracket φ.
      const double delta = 2.0 * kPi / sectors;
      const double u = phi / delta - 0.5;
      const long j = static_cast<long>(std::floor(u));
      const int wrapped = static_cast<int>(((j % sectors) + sectors) % sectors);
      CHECK(w.sector[1] == wrapped);
      CHECK(w.sector[2] == (wrapped + 1) % sectors);
      // Sector j takes 1 − t, its neighbour t: linear in φ between the centres.
      CHECK(w.deposit[1] == Approx(u - static_cast<double>(j)).margin(1e-12));
    }
  }
}

}  // namespace flexref::contact
