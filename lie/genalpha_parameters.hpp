#pragma once
/// \file genalpha_parameters.hpp
/// The coefficients of the Lie-group generalized-α scheme (lie/genalpha.hpp) from the spectral
/// radius at infinity ρ∞ (Chung & Hulbert 1993, as used by Brüls, Cardona & Arnold 2012):
///   α_m = (2ρ∞ − 1)/(ρ∞ + 1),  α_f = ρ∞/(ρ∞ + 1),  γ = ½ + α_f − α_m,  β = ¼ (γ + ½)².
/// ρ∞ = 1 is the trapezoidal rule (no numerical damping); ρ∞ = 0 annihilates the highest
/// frequencies in one step. The registry's `genalpha` takes ρ∞ from the lie::MethodOptions its
/// factory receives (lie/method_options.hpp).
namespace flexref::lie {

/// Default ρ∞ of `genalpha`: 0.9, mild damping of the unresolved high frequencies with second
/// order kept (the paper's own default could not be checked here).
inline constexpr double kDefaultRhoInfinity = 0.9;

struct GenAlphaParameters {
  double rho_inf = kDefaultRhoInfinity;
  double alpha_m = 0.0;
  double alpha_f = 0.0;
  double gamma = 0.0;
  double beta = 0.0;
  /// Arnold's perturbed starting value a_0 = v̇(t_0 + (α_m − α_f) h) instead of a_0 = v̇_0
  /// (docs/schemes.md, "Lie-group generalized-α": the start that avoids the order reduction of
  /// the O(h) transient in a_n, and so in the multipliers).
  bool perturbed_start = false;

  /// The coefficients for ρ∞ ∈ [0, 1]; throws std::invalid_argument otherwise, naming ρ∞.
  static GenAlphaParameters from_rho_inf(double rho_inf);
};

}  // namespace flexref::lie
