#pragma once
/// \file continuous_extension.hpp
/// Dense output of the method's order for the explicit one-step references, which have none of
/// their own at order 8 (Boost.Odeint's RKF7(8); ARKODE's Hermite interpolant stops at degree
/// 5). On an accepted step [t0, t0 + h] the solution is sampled at the four nodes
/// t_j = t0 + (j/3) h, j = 0…3 — the ends are the step's own values, the two interior values
/// are steps of the same method of length h/3 and 2h/3 from the accepted start (each as
/// accurate as the accepted step, being shorter) — and the derivative f(t_j, x_j) is taken at
/// each. Outputs inside the step come from the Hermite polynomial of degree 7 through the eight
/// conditions:
///   p(s) = Σ_k c_k Π_{i<k} (s − z_i),  s = (t − t0)/h,  z = (0, 0, ⅓, ⅓, ⅔, ⅔, 1, 1),
/// c_k the divided differences with repeated nodes (p' = h f at each node).
/// Its error is x⁽⁸⁾(ξ)/8! Π_j (t − t_j)² ≤ 3.8e-9 h⁸ max|x⁽⁸⁾| — order 8 in h, one more than
/// the global order of a 7(8) pair run with local extrapolation: the interpolant does not lower
/// the method's order, and the step sequence stays the tolerance's (tests: order and
/// polynomial exactness in continuous_extension_test.cpp).
#include <array>
#include <vector>

namespace flexref::reference {

class ContinuousExtension {
 public:
  static constexpr int kNodes = 4;
  /// Node j at t0 + node_fraction(j)·h.
  static constexpr double node_fraction(int j) { return static_cast<double>(j) / 3.0; }

  explicit ContinuousExtension(int size = 0);
  void resize(int size);
  int size() const { return size_; }

  /// Fits the polynomial of one step: x[j] and f[j] the state and its derivative at node j (each
  /// `size` values). Allocates nothing.
  void fit(double t0, double h, const std::array<const double*, kNodes>& x,
           const std::array<const double*, kNodes>& f);
  /// p(t), t in [t0, t0 + h]. Allocates nothing.
  void evaluate(double t, double* out) const;

  double start() const { return t0_; }
  double end() const { return t0_ + h_; }

 private:
  int size_ = 0;
  double t0_ = 0.0;
  double h_ = 0.0;
  std::vector<double> coefficients_;  ///< 8 per component, component-major
};

}  // namespace flexref::reference
