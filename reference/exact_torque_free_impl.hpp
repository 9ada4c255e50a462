#pragma once
/// \file exact_torque_free_impl.hpp
/// The bodies of the templates declared in exact_torque_free.hpp, written once for any scalar
/// type S. Include only where the templates are explicitly instantiated
/// (exact_torque_free.cpp: double; precision/exact_solution_instances.cpp: long double,
/// float128 — that file includes <boost/multiprecision/eigen.hpp> first for Eigen's
/// NumTraits). Math goes through argument-dependent lookup (`using std::sqrt; sqrt(x)`) so that
/// boost::multiprecision's overloads are found.
#include <algorithm>
#include <array>
#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>
#include <boost/math/special_functions/ellint_rj.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "reference/exact_rotation_tpl.hpp"
#include "reference/exact_torque_free.hpp"

namespace flexref::reference {

namespace detail {

template <typename S>
S square(S x) {
  return x * x;
}

template <typename S>
bool is_odd(S integral_value) {
  using std::fmod;
  return fmod(integral_value, S(2)) != S(0);
}

/// Relative tolerance of the identities k² + k'² = 1 and n + (1 − n) = 1 at the entry of the
/// elliptic routines: both hold to a few ε when the caller forms them from well-conditioned
/// formulas; 4096 ε (9.1e-13 in double, 1.9e-31 in quad) only catches unrelated numbers.
template <typename S>
S identity_tolerance() {
  return S(4096) * std::numeric_limits<S>::epsilon();
}

template <typename S>
std::string text(const S& x) {
  return std::to_string(static_cast<double>(x));
}

template <typename S>
void check_modulus(S k, S k_prime) {
  using std::abs;
  if (!(k >= S(0)) || !(k_prime >= S(0)) ||
      abs(k * k + k_prime * k_prime - S(1)) > identity_tolerance<S>()) {
    throw std::invalid_argument("elliptic: need k, k' >= 0 with k^2 + k'^2 = 1, got k = " +
                                text(k) + ", k' = " + text(k_prime));
  }
}

template <typename S>
Eigen::Matrix<S, 4, 1> unit_euler_parameters(const Eigen::Matrix<S, 4, 1>& theta, const char* who) {
  using std::abs;
  const S norm = theta.norm();
  // The 1e-6 is scenes.md's rule for the data, not a rounding threshold.
  if (!theta.allFinite() || abs(norm - S(1)) > S(1e-6)) {
    throw std::invalid_argument(
        std::string(who) + ": initial Euler parameters must be unit, |theta0| = " + text(norm));
  }
  return theta / norm;
}

}  // namespace detail

template <typename S>
Eigen::Matrix<S, 4, 1> zxz_euler_parameters(S phi, S cos_half_theta, S sin_half_theta, S psi) {
  using std::cos;
  using std::sin;
  // q_z(φ) ⊗ q_x(ϑ) ⊗ q_z(ψ) multiplied out.
  const S half_sum = S(0.5) * (phi + psi);
  const S half_difference = S(0.5) * (phi - psi);
  return Eigen::Matrix<S, 4, 1>(
      cos_half_theta * cos(half_sum), sin_half_theta * cos(half_difference),
      sin_half_theta * sin(half_difference), cos_half_theta * sin(half_sum));
}

namespace elliptic {

template <typename S>
JacobiValuesTpl<S> jacobi(S u, S k, S k_prime) {
  using std::atan2;
  using std::cos;
  using std::cosh;
  using std::hypot;
  using std::ldexp;
  using std::nearbyint;
  using std::sin;
  using std::sqrt;
  using std::tanh;
  detail::check_modulus(k, k_prime);
  if (k_prime == S(0)) {
    const S sech = S(1) / cosh(u);
    return {tanh(u), sech, sech};
  }
  // AGM: c_n/a_n falls quadratically once below 1; before that it takes about
  // log₂ ln(1/k') levels to get there (≤ 14 for the smallest normal k' of any of the three
  // precisions, 1e-4951 in extended and quad), then log₂ of the mantissa bits (≤ 7 for quad's
  // 113) to reach c ≤ ε a: 40 levels never run out.
  constexpr std::size_t kMaxLevels = 40;
  // AGM stop c_N ≤ ε a_N: the next level would change φ by less than a rounding.
  const S eps = std::numeric_limits<S>::epsilon();
  std::array<S, kMaxLevels + 1> a{};
  std::array<S, kMaxLevels + 1> b{};
  std::array<S, kMaxLevels + 1> c{};
  a[0] = S(1);
  b[0] = k_prime;
  c[0] = k;
  std::size_t levels = 0;
  while (c[levels] > eps * a[levels] && levels < kMaxLevels) {
    a[levels + 1] = S(0.5) * (a[levels] + b[levels]);
    b[levels + 1] = sqrt(a[levels] * b[levels]);
    // c_{n+1} = (a_n − b_n)/2 = c_n²/(4 a_{n+1}), the second form without cancellation.
    c[levels + 1] = S(0.25) * c[levels] * c[levels] / a[levels + 1];
    ++levels;
  }
  // K = π/(2 a_N); reduce u to r ∈ [−K, K], r = u − 2K j.
  const S half_period = boost::math::constants::pi<S>() / a[levels];
  const S j = nearbyint(u / half_period);
  const S r = u - half_period * j;
  S phi = ldexp(a[levels] * r, static_cast<int>(levels));  // φ_N = 2^N a_N r
  for (std::size_t n = levels; n >= 1; --n) {
    const S s = sin(phi);
    phi = S(0.5) * (phi + atan2(c[n] * s, hypot(a[n] * cos(phi), b[n] * s)));
  }
  const S sign = detail::is_odd(j) ? S(-1) : S(1);
  const S sn = sin(phi);
  const S cn = cos(phi);
  // dn² = cn² + k'² sn² (= 1 − k² sn²), free of cancellation near k = 1.
  return {sign * sn, sign * cn, hypot(cn, k_prime * sn)};
}

template <typename S>
S complete_k(S k_prime) {
  if (k_prime == S(0)) return std::numeric_limits<S>::infinity();
  return boost::math::ellint_rf(S(0), k_prime * k_prime, S(1));
}

template <typename S>
S incomplete_f(S sin_am, S cos_am, S k_prime) {
  using std::copysign;
  using std::hypot;
  const S norm = hypot(sin_am, cos_am);
  const S s = sin_am / norm;
  const S c = cos_am / norm;
  const S partial = s * boost::math::ellint_rf(c * c, c * c + detail::square(S(k_prime * s)), S(1));
  if (c >= S(0)) return partial;
  // am ∈ (π/2, π]: F(am) = 2K − F(π − am); am ∈ (−π, −π/2): F(am) = −2K − F(−π − am).
  return copysign(S(2) * complete_k(k_prime), s) - partial;
}

template <typename S>
CircularPiTpl<S>::CircularPiTpl(S n, S one_minus_n, S k, S k_prime)
    : n_(n), k_complete_(complete_k(k_prime)) {
  using std::abs;
  detail::check_modulus(k, k_prime);
  if (!(n >= S(0)) || !(one_minus_n > S(0)) ||
      abs(n + one_minus_n - S(1)) > detail::identity_tolerance<S>()) {
    throw std::invalid_argument("CircularPi: need 0 <= n < 1, got n = " + detail::text(n) +
                                ", 1 - n = " + detail::text(one_minus_n));
  }
  complete_ = k_complete_;
  if (n_ > S(0)) {
    complete_ += n_ / S(3) * boost::math::ellint_rj(S(0), k_prime * k_prime, S(1), one_minus_n);
  }
}

template <typename S>
S CircularPiTpl<S>::operator()(S tau, const JacobiValuesTpl<S>& f, S p) const {
  using std::nearbyint;
  const S j = nearbyint(tau / (S(2) * k_complete_));
  const S s = detail::is_odd(j) ? S(-f.sn) : f.sn;  // sn of the reduced argument τ − 2Kj
  const S c2 = f.cn * f.cn;
  const S d2 = f.dn * f.dn;
  S value = s * boost::math::ellint_rf(c2, d2, S(1));
  if (n_ > S(0)) value += n_ / S(3) * s * s * s * boost::math::ellint_rj(c2, d2, S(1), p);
  return S(2) * j * complete_ + value;
}

template <typename S>
ShiftedHyperbolicPiTpl<S>::ShiftedHyperbolicPiTpl(S nu, S k, S k_prime)
    : nu_(nu),
      k2_(k * k),
      k_prime_(k_prime),
      weight_(nu * k_prime * k_prime / (S(1) + nu)),
      pi_((k * k + nu) / (S(1) + nu), k_prime * k_prime / (S(1) + nu), k, k_prime) {
  if (!(nu >= S(0)) || k2_ + nu_ == S(0)) {
    throw std::invalid_argument("ShiftedHyperbolicPi: need nu >= 0 and k^2 + nu > 0, got nu = " +
                                detail::text(nu) + ", k = " + detail::text(k));
  }
}

template <typename S>
S ShiftedHyperbolicPiTpl<S>::operator()(S tau, const JacobiValuesTpl<S>& f) const {
  const S sigma = tau - pi_.quarter_period();
  // sn, cn, dn(τ − K) = −cd τ, k' sd τ, k' nd τ.
  const S inverse_dn = S(1) / f.dn;
  const JacobiValuesTpl<S> shifted{S(-f.cn * inverse_dn), S(k_prime_ * f.sn * inverse_dn),
                                   S(k_prime_ * inverse_dn)};
  const S p = k_prime_ * k_prime_ * (S(1) + nu_ * f.sn * f.sn) /
              ((S(1) + nu_) * f.dn * f.dn);  // 1 − n' sn²σ
  return (k2_ * sigma + weight_ * pi_(sigma, shifted, p)) / (k2_ + nu_);
}

}  // namespace elliptic

template <typename S>
TorqueFreeExactTpl<S>::TorqueFreeExactTpl(const Vector3& inertia_B, const Quaternion& theta0,
                                          const Vector3& w0_B)
    : regime_(TorqueFreeRegime::kSteadyRotation),
      inertia_B_(inertia_B),
      theta0_(detail::unit_euler_parameters<S>(theta0, "TorqueFreeExact")),
      w0_B_(w0_B) {
  using std::abs;
  using std::asinh;
  using std::copysign;
  using std::hypot;
  using std::sqrt;
  if (!inertia_B.allFinite() || !(inertia_B.minCoeff() > S(0))) {
    throw std::invalid_argument("TorqueFreeExact: principal inertia must be finite and > 0");
  }
  if (!w0_B.allFinite()) {
    throw std::invalid_argument("TorqueFreeExact: initial angular velocity must be finite");
  }
  const Vector3 m0_B = inertia_B.cwiseProduct(w0_B);
  momentum_norm_ = m0_B.norm();
  if (momentum_norm_ == S(0) || m0_B.cross(w0_B).isZero(S(0))) return;  // permanent rotation
  const Vector3 mu0 = m0_B / momentum_norm_;                            // m/M
  const Vector3& inertia = inertia_B_;

  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(),
                   [&inertia](int i, int j) { return inertia(i) < inertia(j); });
  const int i_min = order[0];
  const int i_mid = order[1];
  const int i_max = order[2];
  // (M² − 2E I_mid)/M² as the difference of two non-negative terms; its rounding error is a
  // few ε times their sum, the same size as the effect of rounding the inputs.
  const S term_max =
      detail::square(S(mu0(i_max))) * (inertia(i_max) - inertia(i_mid)) / inertia(i_max);
  const S term_min =
      detail::square(S(mu0(i_min))) * (inertia(i_mid) - inertia(i_min)) / inertia(i_min);
  const S delta = term_max - term_min;
  // On the separatrix only to within rounding (8 ε of S times the terms: each term carries
  // ≤ 4 roundings of ε/2 from μ², the difference and the quotient, the subtraction one more):
  // a looser threshold (say |k'²| < 1e-12) would be wrong, since a state with k' > 0 turns
  // back after τ ≈ 2K ≈ ln(16/k'²), while the separatrix solution never does; the AGM path is
  // accurate for any k' > 0.
  const bool separatrix =
      abs(delta) <= S(8) * std::numeric_limits<S>::epsilon() * (term_max + term_min);
  if (separatrix) {
    ia_ = i_min;
    ib_ = i_mid;
    ic_ = i_max;
    const bool distinct = inertia(ia_) < inertia(ib_) && inertia(ib_) < inertia(ic_);
    if (!distinct || mu0(ia_) == S(0) || mu0(ic_) == S(0)) return;  // permanent rotation
    regime_ = TorqueFreeRegime::kSeparatrix;
  } else if (delta > S(0)) {
    ia_ = i_min;
    ib_ = i_mid;
    ic_ = i_max;
    regime_ = TorqueFreeRegime::kCirculationMaxAxis;
  } else {
    ia_ = i_max;
    ib_ = i_mid;
    ic_ = i_min;
    regime_ = TorqueFreeRegime::kCirculationMinAxis;
  }
  ix_ = (ia_ + 1) % 3;
  iy_ = (ia_ + 2) % 3;

  const S ja = inertia(ia_), jb = inertia(ib_), jc = inertia(ic_);
  const S ma = mu0(ia_), mb = mu0(ib_), mc = mu0(ic_);
  // (2E I_c − M²)/M² and (M² − 2E I_a)/M²: sums of same-sign terms in either labelling.
  const S s_ca = ma * ma * (jc - ja) / ja + mb * mb * (jc - jb) / jb;
  const S s_ac = mb * mb * (jb - ja) / jb + mc * mc * (jc - ja) / jc;
  if (s_ca == S(0)) {  // m along c to within underflow: permanent rotation
    regime_ = TorqueFreeRegime::kSteadyRotation;
    return;
  }
  const S amp_a = sqrt(s_ca * ja / (jc - ja));
  const S amp_b = sqrt(s_ca * jb / (jc - jb));
  const S amp_c = sqrt(s_ac * jc / (jc - ja));
  lambda_ = momentum_norm_ * sqrt((jc - jb) * s_ac / (ja * jb * jc));

  // Signs from ṁ_a = σ m_b m_c (1/I_c − 1/I_b), σ the parity of (a, b, c):
  // A_a λ = σ A_b A_c (I_c − I_b)/(I_b I_c).
  const S parity = (ib_ == (ia_ + 1) % 3) ? S(1) : S(-1);
  const S sign_a = (regime_ == TorqueFreeRegime::kSeparatrix) ? copysign(S(1), ma) : S(1);
  sign_c_ = copysign(S(1), mc);
  const S sign_b = parity * sign_a * sign_c_ * ((jc > jb) ? S(1) : S(-1));
  amp_a_ = sign_a * amp_a;
  amp_b_ = sign_b * amp_b;
  amp_c_ = sign_c_ * amp_c;
  nu_ = (amp_a * amp_a) / (amp_c * amp_c);
  phi_rate_ = momentum_norm_ / ja;
  phi_coeff_ = (jc - ja) / (jc * lambda_);

  if (regime_ == TorqueFreeRegime::kSeparatrix) {
    k_ = S(1);
    k_prime_ = S(0);
    // tanh τ₀ = m_b/A_b, sech τ₀ = |(m_a, m_c)|/|(A_a, A_c)|.
    tau0_ = asinh(sign_b * mb * hypot(amp_a, amp_c) / hypot(ma, mc));
    h0_ = separatrix_h(tau0_);
  } else {
    const S k2 = (jb - ja) * s_ca / ((jc - jb) * s_ac);
    const S k_prime2 = (jc - ja) * delta / ((jc - jb) * s_ac);
    k_ = sqrt(k2);
    k_prime_ = sqrt(k_prime2);
    // cn τ₀ = m_a/A_a, sn τ₀ = m_b/A_b.
    tau0_ = elliptic::incomplete_f<S>(mb / amp_b_, ma / amp_a_, k_prime_);
    phi_integral_.emplace(nu_, k_, k_prime_);
    h0_ = (*phi_integral_)(tau0_, elliptic::jacobi<S>(tau0_, k_, k_prime_));
  }

  detail::Matrix3<S> permutation = detail::Matrix3<S>::Zero();  // body → (x, y, a) coordinates
  permutation(0, ix_) = S(1);
  permutation(1, iy_) = S(1);
  permutation(2, ia_) = S(1);
  q_perm_ = detail::euler_parameters_from_matrix<S>(permutation).normalized();
  // R_π = A(θ₀) Pᵀ R'(0)ᵀ, with R'(0) from the same evaluation as at(0) (φ(0) = 0).
  Vector3 w_B;
  const Quaternion q_euler0 = euler_part(S(0), w_B);
  q_pi_ = detail::quaternion_multiply<S>(
              detail::quaternion_multiply<S>(theta0_, detail::quaternion_conjugate<S>(q_perm_)),
              detail::quaternion_conjugate<S>(q_euler0))
              .normalized();
}

template <typename S>
S TorqueFreeExactTpl<S>::separatrix_h(S tau) const {
  using std::atan;
  using std::sqrt;
  using std::tanh;
  // ∫₀^τ dτ'/(1 + ν tanh²τ') = (τ + √ν atan(√ν tanh τ))/(1 + ν).
  const S root_nu = sqrt(nu_);
  return (tau + root_nu * atan(root_nu * tanh(tau))) / (S(1) + nu_);
}

template <typename S>
S TorqueFreeExactTpl<S>::period() const {
  if (regime_ == TorqueFreeRegime::kSteadyRotation || regime_ == TorqueFreeRegime::kSeparatrix) {
    return std::numeric_limits<S>::infinity();
  }
  return S(4) * elliptic::complete_k<S>(k_prime_) / lambda_;
}

template <typename S>
RigidAttitudeTpl<S> TorqueFreeExactTpl<S>::at(S t) const {
  if (regime_ == TorqueFreeRegime::kSteadyRotation) {
    return {detail::quaternion_multiply<S>(theta0_, detail::exp_quaternion<S>(w0_B_ * t)), w0_B_};
  }
  RigidAttitudeTpl<S> result;
  const Quaternion q_euler = euler_part(t, result.w_B);
  result.theta =
      detail::quaternion_multiply<S>(detail::quaternion_multiply<S>(q_pi_, q_euler), q_perm_);
  return result;
}

template <typename S>
typename TorqueFreeExactTpl<S>::Quaternion TorqueFreeExactTpl<S>::euler_part(S t,
                                                                             Vector3& w_B) const {
  using std::atan2;
  using std::cos;
  using std::cosh;
  using std::hypot;
  using std::sin;
  using std::tanh;
  const S tau = lambda_ * t + tau0_;
  elliptic::JacobiValuesTpl<S> f{};
  S h(0);
  if (regime_ == TorqueFreeRegime::kSeparatrix) {
    const S sech = S(1) / cosh(tau);
    f = {tanh(tau), sech, sech};
    h = separatrix_h(tau);
  } else {
    f = elliptic::jacobi<S>(tau, k_, k_prime_);
    h = (*phi_integral_)(tau, f);
  }
  Vector3 mu;  // m_B / M
  mu(ia_) = amp_a_ * f.cn;
  mu(ib_) = amp_b_ * f.sn;
  mu(ic_) = amp_c_ * f.dn;
  w_B = momentum_norm_ * mu.cwiseQuotient(inertia_B_);
  // φ = (M/I_a)(t − (I_c − I_a)/(I_c λ) (H(τ) − H(τ₀))).
  const S phi = phi_rate_ * (t - phi_coeff_ * (h - h0_));
  // ψ = atan2(m_x, m_y), unwrapped: m_c (= m_x or m_y) never changes sign.
  const S psi = atan2(S(sign_c_ * mu(ix_)), S(sign_c_ * mu(iy_))) +
                (sign_c_ < S(0) ? boost::math::constants::pi<S>() : S(0));
  const S half_theta = S(0.5) * atan2(hypot(mu(ix_), mu(iy_)), mu(ia_));
  return zxz_euler_parameters<S>(phi, cos(half_theta), sin(half_theta), psi);
}

}  // namespace flexref::reference
