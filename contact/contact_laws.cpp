#include "contact/contact_laws.hpp"

#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace flexref::contact {
namespace {

/// φ(x) = x − ln(1 + x) for x > −1, by its series x²/2 − x³/3 + … for |x| < 1e-3 (the direct
/// form loses all digits there: x and ln(1 + x) agree to x²/2). Truncating after x⁷/7 leaves
/// a relative error below (2/8)|x|⁶ ≤ 2.5e-19.
double phi(double x) {
  if (std::abs(x) < 1e-3) {
    double term = x;  // xᵏ
    double sum = 0.0;
    for (int k = 2; k <= 7; ++k) {
      term *= x;
      sum += (k % 2 == 0 ? 1.0 : -1.0) * term / k;
    }
    return sum;
  }
  return x - std::log1p(x);
}

/// Relative tolerance of the root finders: 48 of the 53 bits, so that the restitution
/// recomputed from α (hunt_crossley_restitution) agrees to ~1e-14.
constexpr int kRootBits = 48;

template <typename F>
double solve_bracketed(F f, double lo, double hi) {
  std::uintmax_t iterations = 200;
  const std::pair<double, double> r = boost::math::tools::toms748_solve(
      f, lo, hi, boost::math::tools::eps_tolerance<double>(kRootBits), iterations);
  return 0.5 * (r.first + r.second);
}

void require_law(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

double hunt_crossley_alpha_times_speed(double restitution) {
  const double e = restitution;
  require_law(e > 0.0 && e <= 1.0, "Hunt-Crossley restitution must lie in (0, 1]");
  if (e == 1.0) return 0.0;
  // Unknown a = α v⁻ ∈ ((1 − e)/e, 1/e): f(a) = φ(a) − φ(−a e) rises on (0, (1 − e)/e) and
  // falls to −∞ as a e → 1, so its only positive root is there. Parametrize the rebound side
  // by u = −ln(1 − a e) ∈ (−ln e, ∞) so that a e near 1 stays representable: a e = 1 − e^{−u},
  // and f(u) < 0 for u > 1/e + 2 since φ(a) ≤ a ≤ 1/e and φ(−a e) = u − a e ≥ u − 1.
  auto f = [e](double u) {
    const double x = std::expm1(-u);  // −a e
    return phi(-x / e) - phi(x);
  };
  const double u = solve_bracketed(f, -std::log(e), 1.0 / e + 2.0);
  return -std::expm1(-u) / e;
}

double hunt_crossley_restitution(double alpha_times_speed) {
  const double a = alpha_times_speed;
  require_law(a >= 0.0 && std::isfinite(a), "Hunt-Crossley alpha v must be finite and >= 0");
  const double target = phi(a);
  if (target <= 0.0) return 1.0;
  // b = a e = 1 − e^{−u}: φ(−b) rises from 0 (u = 0) to φ(−b) = u − b ≥ u − 1 (so u = φ(a) + 1
  // brackets the root).
  auto g = [target](double u) { return phi(std::expm1(-u)) - target; };
  const double u = solve_bracketed(g, 0.0, target + 1.0);
  return -std::expm1(-u) / a;
}

double linear_restitution_with_clamp(double zeta) {
  require_law(zeta >= 0.0 && zeta < std::numbers::sqrt2 / 2.0,
              "clamped linear restitution needs 0 <= zeta < 1/sqrt(2)");
  // δ = (v⁻/ω_d) e^{−ζωt} sin ω_d t; k δ + c δ̇ = 0 ⇔ tan ω_d t = −2ζ√(1−ζ²)/(1 − 2ζ²) = −tan 2β
  // with ζ = sin β, so ω_d t* = π − 2β, and there δ̇ = −v⁻ e^{−ζω t*} exactly.
  return std::exp(-zeta * (std::numbers::pi - 2.0 * std::asin(zeta)) /
                  std::sqrt(1.0 - zeta * zeta));
}

NormalLaw NormalLaw::linear(double stiffness, double damping) {
  require_law(stiffness > 0.0 && std::isfinite(stiffness), "contact stiffness must be > 0");
  require_law(damping >= 0.0 && std::isfinite(damping), "contact damping must be >= 0");
  NormalLaw law;
  law.kind_ = Kind::kLinear;
  law.k_ = stiffness;
  law.n_ = 1.0;
  law.c_ = damping;
  law.e_ = std::numeric_limits<double>::quiet_NaN();
  law.v_ref_ = std::numeric_limits<double>::quiet_NaN();
  return law;
}

NormalLaw NormalLaw::linear_from_restitution(double stiffness, double restitution,
                                             double effective_mass) {
  require_law(restitution > 0.0 && restitution <= 1.0, "contact restitution must lie in (0, 1]");
  require_law(effective_mass > 0.0 && std::isfinite(effective_mass),
              "contact effective mass must be > 0");
  // Damped oscillator m δ̈ + c δ̇ + k δ = 0 over half a damped period: e = exp(−ζπ/√(1 − ζ²)).
  const double log_e = std::log(restitution);
  const double zeta = -log_e / std::sqrt(std::numbers::pi * std::numbers::pi + log_e * log_e);
  NormalLaw law = linear(stiffness, 2.0 * zeta * std::sqrt(stiffness * effective_mass));
  law.e_ = restitution;
  return law;
}

NormalLaw NormalLaw::hunt_crossley(double stiffness, double exponent, double restitution,
                                   double reference_speed) {
  require_law(stiffness > 0.0 && std::isfinite(stiffness), "contact stiffness must be > 0");
  require_law(exponent >= 1.0 && std::isfinite(exponent), "Hunt-Crossley exponent must be >= 1");
  require_law(reference_speed > 0.0 && std::isfinite(reference_speed),
              "Hunt-Crossley reference speed must be > 0");
  NormalLaw law;
  law.kind_ = Kind::kHuntCrossley;
  law.k_ = stiffness;
  law.n_ = exponent;
  law.e_ = restitution;
  law.v_ref_ = reference_speed;
  law.alpha_ = hunt_crossley_alpha_times_speed(restitution) / reference_speed;
  return law;
}

double NormalLaw::linearized_stiffness(double delta) const {
  if (kind_ == Kind::kLinear) return k_;
  return delta > 0.0 ? n_ * k_ * std::pow(delta, n_ - 1.0) : 0.0;
}

double NormalLaw::linearized_damping(double delta) const {
  if (kind_ == Kind::kLinear) return c_;
  return delta > 0.0 ? alpha_ * k_ * std::pow(delta, n_) : 0.0;
}

double NormalLaw::impact_penetration(double effective_mass, double speed) const {
  // ½ m v² = k δⁿ⁺¹/(n + 1)
  return std::pow((n_ + 1.0) * 0.5 * effective_mass * speed * speed / k_, 1.0 / (n_ + 1.0));
}

std::string NormalLaw::describe() const {
  std::ostringstream out;
  if (kind_ == Kind::kLinear) {
    out << "linear k = " << k_ << " N/m, c = " << c_ << " N*s/m";
    if (!std::isnan(e_)) out << " (e = " << e_ << ")";
  } else {
    out << "Hunt-Crossley k = " << k_ << " N/m^" << n_ << ", n = " << n_ << ", e = " << e_
        << " at v_ref = " << v_ref_ << " m/s (alpha = " << alpha_ << " s/m)";
  }
  return out.str();
}

}  // namespace flexref::contact
