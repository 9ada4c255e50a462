#pragma once
/// \file worn_profile_tpl.hpp
/// The worn depth around a circular gap support (docs/wear.md, "Wear laws"), from the depths h_j
/// of its S angular sectors, generic in the scalar type S:
///
/// - sector j spans [jΔ, (j+1)Δ), Δ = 2π/S, its depth h_j belongs to its centre φ_j = (j + ½)Δ;
/// - the depth at an angle φ is the periodic Catmull–Rom spline through the centres: with
///   u = φ/Δ − ½, j = ⌊u⌋, t = u − j ∈ [0, 1),
///     h(φ) = Σ_{m=0..3} b_m(t) h_{j−1+m},
///     b_0 = ½(−t + 2t² − t³), b_1 = ½(2 − 5t² + 3t³), b_2 = ½(t + 4t² − 3t³), b_3 = ½(t³ − t²)
///   (Catmull & Rom 1974, the cubic Hermite spline with the centred slopes ½(h_{j+1} − h_{j−1})):
///   C¹ in φ, so the support's force is continuous where the contact moves from sector to sector
///   (a piecewise-constant profile would make it jump, and every reference step across a
///   boundary a discontinuity), and exact for a uniform depth;
/// - a contact at φ wears the two sectors whose centres bracket it, sector j by (1 − t) and
///   sector j+1 by t of the volume: hat weights, ≥ 0 and summing to 1, so the worn volume is
///   conserved and no sector ever un-wears.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <numbers>
#include <span>

namespace flexref::contact {

/// The spline's four sectors and weights at an angle, with the weights' derivatives in φ and the
/// two sectors and hat weights of the deposit.
template <typename S>
struct WornProfileWeightsTpl {
  std::array<int, 4> sector{};  ///< j−1, j, j+1, j+2 (mod S)
  std::array<S, 4> value{};     ///< b_m(t)
  std::array<S, 4> slope{};     ///< db_m/dφ, 1/rad
  std::array<S, 2> deposit{};   ///< 1 − t on sector j, t on sector j+1
};

/// The weights at angle φ (rad, any real value) for `sectors` ≥ 1 sectors.
template <typename S>
WornProfileWeightsTpl<S> worn_profile_weights(const S& phi, int sectors) {
  using std::floor;
  WornProfileWeightsTpl<S> w;
  const S delta = S(2) * S(std::numbers::pi_v<double>) / S(sectors);
  const S u = phi / delta - S(0.5);
  const S j = floor(u);
  const S t = u - j;
  const auto wrap = [sectors](long k) {
    return static_cast<int>(((k % sectors) + sectors) % sectors);
  };
  const long j0 = static_cast<long>(static_cast<double>(j));
  for (int m = 0; m < 4; ++m) w.sector[static_cast<std::size_t>(m)] = wrap(j0 - 1 + m);
  const S t2 = t * t;
  const S t3 = t2 * t;
  w.value = {S(0.5) * (-t + S(2) * t2 - t3), S(0.5) * (S(2) - S(5) * t2 + S(3) * t3),
             S(0.5) * (t + S(4) * t2 - S(3) * t3), S(0.5) * (t3 - t2)};
  // d/dφ = (1/Δ) d/dt
  w.slope = {
      S(0.5) * (S(-1) + S(4) * t - S(3) * t2) / delta, S(0.5) * (S(-10) * t + S(9) * t2) / delta,
      S(0.5) * (S(1) + S(8) * t - S(9) * t2) / delta, S(0.5) * (S(3) * t2 - S(2) * t) / delta};
  w.deposit = {S(1) - t, t};
  return w;
}

/// h(φ) and h'(φ) (m, m/rad) from the sector depths and the weights at φ.
template <typename S>
std::array<S, 2> worn_profile_at(const WornProfileWeightsTpl<S>& w, std::span<const S> depth) {
  std::array<S, 2> h{S(0), S(0)};
  for (std::size_t m = 0; m < 4; ++m) {
    const S& d = depth[static_cast<std::size_t>(w.sector[m])];
    h[0] += w.value[m] * d;
    h[1] += w.slope[m] * d;
  }
  return h;
}

}  // namespace flexref::contact
