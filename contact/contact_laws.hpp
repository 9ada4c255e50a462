#pragma once
/// \file contact_laws.hpp
/// Penalty laws of a contact (docs/contact.md): the normal force as a function of the
/// penetration δ = −gap ≥ 0 and its rate δ̇, and regularized Coulomb friction.
///
/// Normal laws (the contact never pulls: the total force is clamped at ≥ 0):
///   linear spring–dashpot  F = max(0, k δ + c δ̇),               V = ½ k δ²
///   Hunt–Crossley          F = max(0, k δⁿ (1 + α δ̇)),          V = k δⁿ⁺¹/(n + 1)
/// Friction (smooth regularized Coulomb):
///   F_t = −μ F_n tanh(|v_t|/v_reg) v_t/|v_t|
/// Units: k in N/m (linear) or N/mⁿ (Hunt–Crossley), c in N·s/m, α in s/m, speeds in m/s.
///
/// The laws are written once, generic in the scalar type (force_in, potential_in,
/// slip_factor_in): the double model calls them with double, the extended/quad references of
/// precision/ with long double and float128 (docs/precision.md); the parameters stay the
/// scene's doubles, so every precision solves the same model.
#include <cmath>
#include <string>
#include <type_traits>

namespace flexref::contact {

/// Normal force split into its elastic part (derivative of the potential) and the total.
template <typename S>
struct NormalForceTpl {
  S total = S(0);    ///< F ≥ 0, N
  S elastic = S(0);  ///< F_e = dV/dδ, N
  /// Non-conservative part F − F_e (damping, and the clamp when it is active), N.
  S dissipative() const { return total - elastic; }
};
using NormalForce = NormalForceTpl<double>;

/// The normal law of a contact. Immutable; built by the named constructors below.
class NormalLaw {
 public:
  enum class Kind { kLinear, kHuntCrossley };

  /// Linear spring–dashpot with stiffness k (N/m) and damping c (N·s/m).
  static NormalLaw linear(double stiffness, double damping);
  /// Linear spring–dashpot whose damping gives the restitution e ∈ (0, 1] to a mass m_eff
  /// (kg) without the clamp: ζ = −ln e / √(π² + ln² e), c = 2 ζ √(k m_eff).
  static NormalLaw linear_from_restitution(double stiffness, double restitution,
                                           double effective_mass);
  /// Hunt–Crossley F = k δⁿ (1 + α δ̇) with α chosen so that an impact at v_ref (m/s)
  /// rebounds with exactly e ∈ (0, 1] (hunt_crossley_alpha_times_speed).
  static NormalLaw hunt_crossley(double stiffness, double exponent, double restitution,
                                 double reference_speed);

  Kind kind() const { return kind_; }
  double stiffness() const { return k_; }
  double exponent() const { return n_; }
  /// Linear law: c (N·s/m); Hunt–Crossley: 0 (see alpha()).
  double damping() const { return c_; }
  /// Hunt–Crossley α (s/m); 0 for the linear law.
  double alpha() const { return alpha_; }
  /// The restitution the law was built for (NaN for linear(k, c)).
  double restitution() const { return e_; }
  /// Hunt–Crossley v_ref (m/s); NaN for the linear law.
  double reference_speed() const { return v_ref_; }

  /// Force at penetration δ (< 0 gives zero: separated) and rate δ̇ (m/s).
  NormalForce force(double delta, double delta_dot) const { return force_in(delta, delta_dot); }
  /// Elastic energy stored at penetration δ (0 when δ ≤ 0), J.
  double potential(double delta) const { return potential_in(delta); }
  /// force() in any precision S.
  template <typename S>
  NormalForceTpl<S> force_in(const S& delta, const S& delta_dot) const;
  /// potential() in any precision S.
  template <typename S>
  S potential_in(const S& delta) const;
  /// The force of a wearing contact (docs/wear.md), whose worn surface recedes at β F while the
  /// bodies approach at u: the penetration rate is δ̇ = u − β F, with β ≥ 0 (m/(N·s)). The law
  /// is affine in δ̇, F = F_e + D δ̇ (D = c, or α F_e for Hunt–Crossley), so
  ///   F = (F_e + D u) / (1 + D β),   clamped at ≥ 0,
  /// which is force_in(δ, u) at β = 0. Its clamp switches where F_e + D u does, as
  /// clamp_function(δ, u) says.
  template <typename S>
  NormalForceTpl<S> force_with_recession_in(const S& delta, const S& approach_rate,
                                            const S& beta) const;
  /// The unclamped law's value, whose sign change is the clamp's switch inside a contact:
  /// k δ + c δ̇ (linear), 1 + α δ̇ (Hunt–Crossley; the clamp acts where it is ≤ 0).
  template <typename S>
  S clamp_function(const S& delta, const S& delta_dot) const;
  /// dF_e/dδ at δ (N/m): k for the linear law, n k δⁿ⁻¹ for Hunt–Crossley.
  double linearized_stiffness(double delta) const;
  /// dF/dδ̇ at δ (N·s/m): c, or α k δⁿ for Hunt–Crossley.
  double linearized_damping(double delta) const;
  /// Largest penetration of an undamped impact of a mass m_eff at speed v:
  /// ½ m v² = V(δ_max).
  double impact_penetration(double effective_mass, double speed) const;
  /// One line: the law and its parameters with units.
  std::string describe() const;

 private:
  Kind kind_ = Kind::kLinear;
  double k_ = 0.0;
  double n_ = 1.0;
  double c_ = 0.0;
  double alpha_ = 0.0;
  double e_ = 0.0;
  double v_ref_ = 0.0;
};

/// Regularized Coulomb friction μ F_n tanh(|v_t|/v_reg), opposing the slip velocity v_t.
/// A load below the friction limit lets the contact creep at
/// |v_t| = v_reg atanh(F_t/(μ F_n)) instead of sticking (docs/contact.md).
struct FrictionLaw {
  double mu = 0.0;      ///< friction coefficient (–)
  double v_reg = 1e-3;  ///< regularization speed, m/s

  /// The factor s of F_t = −μ F_n s v_t: s = tanh(|v_t|/v_reg)/|v_t| (1/v_reg at v_t = 0,
  /// by its series below 1e-4 v_reg), in s/m.
  double slip_factor(double slip_speed) const { return slip_factor_in(slip_speed); }
  /// slip_factor() in any precision S.
  template <typename S>
  S slip_factor_in(const S& slip_speed) const;
};

template <typename S>
NormalForceTpl<S> NormalLaw::force_in(const S& delta, const S& delta_dot) const {
  using std::pow;
  if (!(delta > S(0))) return {};
  NormalForceTpl<S> f;
  S unclamped;
  if (kind_ == Kind::kLinear) {
    f.elastic = k_ * delta;
    unclamped = f.elastic + c_ * delta_dot;
  } else {
    f.elastic = k_ * pow(delta, S(n_));
    unclamped = f.elastic * (S(1) + alpha_ * delta_dot);
  }
  f.total = unclamped > S(0) ? unclamped : S(0);  // the contact never pulls
  return f;
}

template <typename S>
NormalForceTpl<S> NormalLaw::force_with_recession_in(const S& delta, const S& approach_rate,
                                                     const S& beta) const {
  using std::pow;
  if (beta == S(0)) return force_in(delta, approach_rate);
  if (!(delta > S(0))) return {};
  NormalForceTpl<S> f;
  f.elastic = kind_ == Kind::kLinear ? S(k_ * delta) : S(k_ * pow(delta, S(n_)));
  const S damping = kind_ == Kind::kLinear ? S(c_) : S(alpha_ * f.elastic);  // D = ∂F/∂δ̇
  const S unclamped = (f.elastic + damping * approach_rate) / (S(1) + damping * beta);
  f.total = unclamped > S(0) ? unclamped : S(0);  // the contact never pulls
  return f;
}

template <typename S>
S NormalLaw::potential_in(const S& delta) const {
  using std::pow;
  if (!(delta > S(0))) return S(0);
  return k_ * pow(delta, S(n_ + 1.0)) / S(n_ + 1.0);
}

template <typename S>
S NormalLaw::clamp_function(const S& delta, const S& delta_dot) const {
  if (kind_ == Kind::kLinear) return k_ * delta + c_ * delta_dot;
  return S(1) + alpha_ * delta_dot;
}

template <typename S>
S FrictionLaw::slip_factor_in(const S& slip_speed) const {
  using std::tanh;
  const S x = slip_speed / v_reg;
  // tanh(x)/x = 1 − x²/3 + 2x⁴/15 − …: below x = 1e-4 the x⁴ term is < 2e-17 relative, enough
  // for double; in a longer precision the series keeps terms until they fall below its ε.
  if (x < S(1e-4)) {
    if constexpr (std::is_same_v<S, double>) return (1.0 - x * x / 3.0) / v_reg;
    const S x2 = x * x;
    // tanh(x)/x = Σ 2^{2k}(2^{2k} − 1) B_{2k} x^{2k−2}/(2k)!: 1 − x²/3 + 2x⁴/15 − 17x⁶/315 +
    // 62x⁸/2835; at x < 1e-4 the next term is < 1e-41, below float128's ε = 1.9e-34.
    return (S(1) - x2 * (S(1) / 3 - x2 * (S(2) / 15 - x2 * (S(17) / 315 - x2 * S(62) / 2835)))) /
           S(v_reg);
  }
  return tanh(x) / slip_speed;
}

/// The exact Hunt–Crossley relation between restitution and damping (docs/contact.md):
/// with a = α v⁻ and φ(x) = x − ln(1 + x), an impact at v⁻ rebounds with v⁺ = e v⁻ where
/// φ(a) = φ(−a e). Solves it for a given e ∈ (0, 1] (a = 0 for e = 1).
double hunt_crossley_alpha_times_speed(double restitution);
/// Restitution of the clamped linear spring–dashpot (no other force) with damping ratio
/// ζ < 1/√2: the clamp releases at ω_d t* = π − 2 asin ζ, so e = exp(−ζ(π − 2 asin ζ)/√(1 − ζ²)),
/// above the unclamped exp(−ζπ/√(1 − ζ²)).
double linear_restitution_with_clamp(double zeta);
/// The inverse: the restitution of an impact with a = α v⁻ ≥ 0.
double hunt_crossley_restitution(double alpha_times_speed);

}  // namespace flexref::contact
