#pragma once
/// \file exact_torque_free.hpp
/// Exact motion of the torque-free rigid body (Euler–Poinsot), plus the elliptic-function
/// building blocks shared by the exact solutions in reference/ (heavy top, pendulum).
///
/// Sources: L. D. Landau, E. M. Lifshitz, Mechanics, 3rd ed., §37; E. Celledoni, F. Fassò,
/// N. Säfström, A. Zanna, "The exact computation of the free rigid body motion and its use in
/// splitting methods", SIAM J. Sci. Comput. 30(4):2084–2112 (2008); B. C. Carlson, "Numerical
/// computation of real or complex elliptic integrals", Numer. Algorithms 10 (1995);
/// Abramowitz & Stegun §16.4 (arithmetic-geometric mean), §17.7 (Π).
///
/// Written once for any scalar type S (Pinocchio's ModelTpl pattern; docs/precision.md): the
/// templates' bodies are in exact_torque_free_impl.hpp, instantiated for double in
/// exact_torque_free.cpp and for long double and boost::multiprecision::float128 in
/// precision/exact_solution_instances.cpp (only precision/ sees float128). Boost's Carlson
/// integrals are generic, and every threshold that expresses rounding is a multiple of S's ε,
/// so the solutions are exact to a few ε of S. The double names (TorqueFreeExact, RigidAttitude,
/// elliptic::CircularPi, ...) are aliases of the double instantiations.
#include <Eigen/Core>
#include <optional>

#include "rotation/euler_parameters.hpp"

namespace flexref::reference {

/// Attitude and angular velocity of a rigid body at one instant.
template <typename S>
struct RigidAttitudeTpl {
  Eigen::Matrix<S, 4, 1> theta;  ///< Euler parameters, body → global
  Eigen::Matrix<S, 3, 1> w_B;    ///< angular velocity of the body, body frame
};
using RigidAttitude = RigidAttitudeTpl<double>;

/// Euler parameters of the z-x-z Euler-angle rotation
/// \f[ R = R_z(\varphi)\,R_x(\vartheta)\,R_z(\psi) \f]
/// (active rotations, body → reference frame; the convention of Goldstein §4.4 and Landau–
/// Lifshitz §35, whose body-frame angular velocity is
/// \f$\omega = (\dot\varphi\sin\vartheta\sin\psi + \dot\vartheta\cos\psi,\;
/// \dot\varphi\sin\vartheta\cos\psi - \dot\vartheta\sin\psi,\; \dot\varphi\cos\vartheta +
/// \dot\psi)\f$). The half-angle cosine and sine of ϑ are passed separately so that callers can
/// form them from 1 ± cos ϑ without cancellation near ϑ = 0 or π.
template <typename S>
Eigen::Matrix<S, 4, 1> zxz_euler_parameters(S phi, S cos_half_theta, S sin_half_theta, S psi);

namespace detail {
/// θ/|θ| for the initial attitude of an exact solution; `who` names the caller in the error.
/// \throws std::invalid_argument if θ is not finite or ||θ| − 1| > 1e-6 (scenes.md's rule).
template <typename S>
Eigen::Matrix<S, 4, 1> unit_euler_parameters(const Eigen::Matrix<S, 4, 1>& theta, const char* who);
}  // namespace detail

/// Elliptic functions and integrals parametrised by the modulus k AND its complement
/// k' = √(1 − k²), both supplied by the caller. Near k = 1 the complement carries all the
/// information (the period K ≈ ln(4/k')); boost::math::jacobi_elliptic and ellint_1 take k
/// only and recompute k' with relative error ε/k'², which near a separatrix (k' ~ 1e-4) is
/// already 1e-8. Every routine here is accurate to a few ε for any k' > 0.
namespace elliptic {

/// sn, cn, dn at one argument.
template <typename S>
struct JacobiValuesTpl {
  S sn;
  S cn;
  S dn;
};
using JacobiValues = JacobiValuesTpl<double>;

/// Jacobi elliptic functions sn, cn, dn(u, k) by the arithmetic-geometric mean
/// (A&S 16.4.2–16.4.3, started from a₀ = 1, b₀ = k', c₀ = k, with c_{n+1} = c_n²/(4a_{n+1})
/// and the backward recursion written as
/// \f[ \varphi_{n-1} = \tfrac12\Bigl(\varphi_n + \operatorname{atan2}\bigl(c_n\sin\varphi_n,\,
///     \sqrt{a_n^2\cos^2\varphi_n + b_n^2\sin^2\varphi_n}\bigr)\Bigr), \f]
/// which equals A&S's arcsin form but has no cancellation near k = 1). The argument is reduced
/// modulo 2K first (sn, cn change sign, dn is 2K-periodic), so large u costs nothing extra.
/// k' = 0 gives the separatrix limit (tanh, sech, sech).
/// \throws std::invalid_argument unless k, k' ≥ 0 and |k² + k'² − 1| ≤ 4096 ε (9e-13 in
/// double; a few ε when k and k' come from well-conditioned formulas, so this only catches
/// callers that pass unrelated numbers).
template <typename S>
JacobiValuesTpl<S> jacobi(S u, S k, S k_prime);

/// Complete integral of the first kind \f$K(k) = R_F(0, k'^2, 1)\f$ (Carlson).
template <typename S>
S complete_k(S k_prime);

/// Incomplete integral of the first kind \f$F(\mathrm{am}, k)\f$ for an amplitude given by its
/// sine and cosine (need not be normalised), am ∈ (−π, π]:
/// \f$F = s\,R_F(c^2, c^2 + k'^2 s^2, 1)\f$ for c ≥ 0, \f$\pm 2K - s\,R_F(\dots)\f$ otherwise.
/// This is the inverse of jacobi: jacobi(F(am), k, k') = (sin am, cos am, ·).
template <typename S>
S incomplete_f(S sin_am, S cos_am, S k_prime);

/// \f$\Pi_n(\tau) = \int_0^\tau \frac{d\tau'}{1 - n\,\mathrm{sn}^2(\tau', k)}\f$ for
/// 0 ≤ n < 1 (the "circular" case, k² ≤ n, or 0 ≤ n < k²) through Carlson's forms
/// \f[ \Pi_n(\tau) = s R_F(c^2, d^2, 1) + \tfrac{n}{3} s^3 R_J(c^2, d^2, 1, p),\qquad
///     p = 1 - n s^2, \f]
/// on |τ| ≤ K and quasi-periodicity \f$\Pi_n(\tau + 2K) = \Pi_n(\tau) + 2\Pi_n(K)\f$. Both
/// terms are non-negative for s ≥ 0, so nothing cancels even as n → 1, provided the caller
/// passes p = 1 − n sn²τ and 1 − n computed from quantities that do not cancel.
template <typename S>
class CircularPiTpl {
 public:
  CircularPiTpl(S n, S one_minus_n, S k, S k_prime);
  /// Π_n(τ) given sn, cn, dn at τ (full, unreduced argument) and p = 1 − n sn²(τ).
  S operator()(S tau, const JacobiValuesTpl<S>& f, S p) const;
  S complete() const { return complete_; }  ///< Π_n(K)
  S quarter_period() const { return k_complete_; }

 private:
  S n_;
  S k_complete_;  ///< K(k)
  S complete_;    ///< Π_n(K)
};
using CircularPi = CircularPiTpl<double>;

/// \f$H_\nu(\tau) = \int_K^\tau \frac{d\tau'}{1 + \nu\,\mathrm{sn}^2(\tau', k)}\f$ for ν ≥ 0
/// (a characteristic −ν ≤ 0, the "hyperbolic" case). Carlson's direct form cancels
/// catastrophically for ν ≫ 1 (the result is ~π/(2√ν) from O(1) terms), so the integral is
/// shifted by a quarter period: with σ = τ − K, sn²(σ + K) = cd²σ, and
/// \f[ H_\nu(\tau) = \frac{k^2\sigma + \frac{\nu k'^2}{1+\nu}\,\Pi_{n'}(\sigma)}{k^2+\nu},
///     \qquad n' = \frac{k^2+\nu}{1+\nu},\quad 1 - n' = \frac{k'^2}{1+\nu}, \f]
/// a sum of non-negative terms; \f$\mathrm{sn}\,\sigma = -\mathrm{cn}\,\tau/\mathrm{dn}\,\tau\f$,
/// \f$\mathrm{cn}^2\sigma = k'^2\mathrm{sn}^2\tau/\mathrm{dn}^2\tau\f$,
/// \f$\mathrm{dn}^2\sigma = k'^2/\mathrm{dn}^2\tau\f$ and
/// \f$p = 1 - n'\mathrm{sn}^2\sigma = k'^2 (1 + \nu\,\mathrm{sn}^2\tau)/((1+\nu)\,
/// \mathrm{dn}^2\tau)\f$ come from the values at τ (no second AGM).
template <typename S>
class ShiftedHyperbolicPiTpl {
 public:
  /// \throws std::invalid_argument if ν < 0, or if ν = k = 0 (the integrand is 1; use τ).
  ShiftedHyperbolicPiTpl(S nu, S k, S k_prime);
  /// H_ν(τ) given sn, cn, dn at τ (full, unreduced argument).
  S operator()(S tau, const JacobiValuesTpl<S>& f) const;

 private:
  S nu_;
  S k2_;
  S k_prime_;
  S weight_;  ///< ν k'² / (1 + ν)
  CircularPiTpl<S> pi_;
};
using ShiftedHyperbolicPi = ShiftedHyperbolicPiTpl<double>;

}  // namespace elliptic

/// Regimes of the torque-free motion.
enum class TorqueFreeRegime {
  kSteadyRotation,      ///< ω × Jω = 0: permanent rotation (principal axis, or isotropic plane)
  kCirculationMaxAxis,  ///< |π|² > 2E I_mid: the angular momentum circles the max-inertia axis
  kCirculationMinAxis,  ///< |π|² < 2E I_mid: ... circles the min-inertia axis
  kSeparatrix,          ///< |π|² = 2E I_mid to rounding: asymptotic to the middle axis
};

/// Exact torque-free motion of a rigid body with principal inertia diag(I) in the body frame
/// (any ordering; two or three equal moments allowed). With m = J ω the body angular
/// momentum, M = |m| = |π| and 2E = Σ m_i²/I_i, label the axes (a, b, c) so that c is the
/// axis the angular momentum circles (max-inertia axis if M² > 2E I_b, min-inertia axis if
/// M² < 2E I_b), b the middle one, a the remaining extreme one; then (Landau–Lifshitz §37)
/// \f[ m_a = A_a\,\mathrm{cn}\,\tau,\quad m_b = A_b\,\mathrm{sn}\,\tau,\quad
///     m_c = A_c\,\mathrm{dn}\,\tau,\qquad \tau = \lambda t + \tau_0, \f]
/// \f[ A_a^2 = \frac{(2EI_c - M^2) I_a}{I_c - I_a},\; A_b^2 = \frac{(2EI_c - M^2) I_b}{I_c -
///     I_b},\; A_c^2 = \frac{(M^2 - 2EI_a) I_c}{I_c - I_a},\;
///     \lambda^2 = \frac{(I_c - I_b)(M^2 - 2EI_a)}{I_a I_b I_c},\;
///     k^2 = \frac{(I_b - I_a)(2EI_c - M^2)}{(I_c - I_b)(M^2 - 2EI_a)}, \f]
/// \f$k'^2 = (I_c - I_a)(M^2 - 2EI_b)/((I_c - I_b)(M^2 - 2EI_a))\f$, every difference formed as
/// a sum of same-sign terms in the m_i² (e.g. \f$2EI_c - M^2 = \sum_i m_i^2 (I_c - I_i)/I_i\f$),
/// so k' stays accurate at the separatrix. On the separatrix (M² = 2E I_b to rounding) sn, cn,
/// dn become tanh, sech, sech. Signs of A_b, A_c and the phase τ₀ follow from m(0) and the
/// Euler equations ṁ = m × J⁻¹m.
///
/// Orientation (Celledoni–Fassò–Säfström–Zanna 2008): z-x-z Euler angles with the inertial z
/// axis along the constant π and the body z axis along a (the extreme axis the momentum does
/// NOT circle, so sin ϑ never vanishes and no angle is singular), body x, y along the cyclic
/// successors of a:
/// \f[ \cos\vartheta = m_a/M,\quad \psi = \operatorname{atan2}(m_x, m_y),\quad
///     \dot\varphi = M\frac{m_x^2/I_x + m_y^2/I_y}{m_x^2 + m_y^2}
///     = \frac{M}{I_a}\Bigl(1 - \frac{I_c - I_a}{I_c}\,\frac{1}{1 + \nu\,\mathrm{sn}^2\tau}
///     \Bigr),\quad \nu = A_a^2/A_c^2, \f]
/// integrated in closed form: \f$\varphi = \frac{M}{I_a}\bigl(t - \frac{I_c - I_a}{I_c
/// \lambda}[H_\nu(\tau) - H_\nu(\tau_0)]\bigr)\f$ (elliptic::ShiftedHyperbolicPi; on the
/// separatrix \f$H = (\tau + \sqrt\nu\arctan(\sqrt\nu\tanh\tau))/(1+\nu)\f$). The attitude is
/// \f[ R(t) = R_\pi\,R_z(\varphi)R_x(\vartheta)R_z(\psi)\,P, \f]
/// P the cyclic permutation body → (x, y, a), R_π constant, fixed by R(0) = A(θ₀) with
/// φ(0) = 0 (so R_π e_z = π/M). ψ is unwrapped with the constant sign of m_c, so θ(t) is
/// continuous in t (no quaternion sign flips).
///
/// Accuracy (S = double): the phase τ and the secular part of φ are rounded to ~ε·λt and ~ε·Mt/I_a,
/// which bounds the error growth; against RKF78 in float128 at tolerance 1e-24 over t ≤ 100:
/// free_spin ω to 4e-15 relative, θ to 6e-14 rad; book toss 2.4e-6 off the separatrix
/// (k'² = 7e-9) ω to 1.1e-13, θ to 4e-13 rad. at() allocates nothing and costs one AGM
/// (≈ 10 levels) plus one R_F and one R_J (≈ 2 µs).
/// In extended and quad the same holds at their ε (docs/precision.md: quad against a quad
/// Bulirsch–Stoer reference, tests/precision/exact_high_precision_test.cpp).
template <typename S>
class TorqueFreeExactTpl {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Quaternion = Eigen::Matrix<S, 4, 1>;  ///< Euler parameters (e0, e1, e2, e3)

  /// \throws std::invalid_argument for non-finite or non-positive inertia, a non-unit θ₀
  /// (|θ₀| − 1 > 1e-6; smaller deviations are normalised away) or a non-finite ω₀.
  TorqueFreeExactTpl(const Vector3& inertia_B, const Quaternion& theta0, const Vector3& w0_B);

  RigidAttitudeTpl<S> at(S t) const;

  TorqueFreeRegime regime() const { return regime_; }
  /// Elliptic modulus k (0 for steady rotation and symmetric bodies, 1 on the separatrix).
  S modulus() const { return k_; }
  /// Period of ω_B(t) (4K/λ; 2π/λ for symmetric bodies); +∞ on the separatrix and for steady
  /// rotation.
  S period() const;

 private:
  TorqueFreeRegime regime_;
  Vector3 inertia_B_;
  Quaternion theta0_;
  Vector3 w0_B_;
  S momentum_norm_ = S(0);        ///< M = |π|
  int ia_ = 0, ib_ = 1, ic_ = 2;  ///< body indices of the axes a, b, c
  int ix_ = 1, iy_ = 2;           ///< body indices of the Euler x, y axes (cyclic after a)
  S amp_a_ = S(0), amp_b_ = S(0), amp_c_ = S(0);  ///< signed A_a, A_b, A_c divided by M
  S sign_c_ = S(1);                               ///< sign of m_c (constant)
  S lambda_ = S(0), tau0_ = S(0);
  S k_ = S(0), k_prime_ = S(1);
  S nu_ = S(0);                                                      ///< A_a²/A_c²
  S phi_rate_ = S(0);                                                ///< M/I_a
  S phi_coeff_ = S(0);                                               ///< (I_c − I_a)/(I_c λ)
  S h0_ = S(0);                                                      ///< H_ν(τ₀)
  std::optional<elliptic::ShiftedHyperbolicPiTpl<S>> phi_integral_;  ///< H_ν (elliptic regimes)
  Quaternion q_pi_;                                                  ///< R_π
  Quaternion q_perm_;                                                ///< P

  S separatrix_h(S tau) const;
  /// R_z(φ)R_x(ϑ)R_z(ψ) at t, and ω_B(t) (non-steady regimes).
  Quaternion euler_part(S t, Vector3& w_B) const;
};
using TorqueFreeExact = TorqueFreeExactTpl<double>;

extern template class TorqueFreeExactTpl<double>;
extern template class elliptic::CircularPiTpl<double>;
extern template class elliptic::ShiftedHyperbolicPiTpl<double>;

}  // namespace flexref::reference
