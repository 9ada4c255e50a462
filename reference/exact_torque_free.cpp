#include "reference/exact_torque_free.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <boost/math/special_functions/ellint_rf.hpp>
#include <boost/math/special_functions/ellint_rj.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace flexref::reference {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kPi = std::numbers::pi;

double square(double x) { return x * x; }

bool is_odd(double integral_value) { return std::fmod(integral_value, 2.0) != 0.0; }

void check_modulus(double k, double k_prime) {
  // k² + k'² = 1 holds to a few ε when both come from well-conditioned formulas; 1e-12 only
  // catches callers that pass unrelated numbers.
  if (!(k >= 0.0) || !(k_prime >= 0.0) || std::abs(k * k + k_prime * k_prime - 1.0) > 1e-12) {
    throw std::invalid_argument("elliptic: need k, k' >= 0 with k^2 + k'^2 = 1, got k = " +
                                std::to_string(k) + ", k' = " + std::to_string(k_prime));
  }
}

}  // namespace

rotation::EulerParameters zxz_euler_parameters(double phi, double cos_half_theta,
                                               double sin_half_theta, double psi) {
  // q_z(φ) ⊗ q_x(ϑ) ⊗ q_z(ψ) multiplied out.
  const double half_sum = 0.5 * (phi + psi);
  const double half_difference = 0.5 * (phi - psi);
  return rotation::EulerParameters(
      cos_half_theta * std::cos(half_sum), sin_half_theta * std::cos(half_difference),
      sin_half_theta * std::sin(half_difference), cos_half_theta * std::sin(half_sum));
}

namespace detail {

rotation::EulerParameters unit_euler_parameters(const rotation::EulerParameters& theta,
                                                const char* who) {
  const double norm = theta.norm();
  if (!theta.allFinite() || std::abs(norm - 1.0) > 1e-6) {
    throw std::invalid_argument(
        std::string(who) +
        ": initial Euler parameters must be unit, |theta0| = " + std::to_string(norm));
  }
  return theta / norm;
}

}  // namespace detail

namespace elliptic {

JacobiValues jacobi(double u, double k, double k_prime) {
  check_modulus(k, k_prime);
  if (k_prime == 0.0) {
    const double sech = 1.0 / std::cosh(u);
    return {std::tanh(u), sech, sech};
  }
  // AGM: c_n/a_n falls quadratically once below 1; from k' = 1e-300 it takes ~10 levels to get
  // there, so 40 levels never run out.
  constexpr std::size_t kMaxLevels = 40;
  std::array<double, kMaxLevels + 1> a{};
  std::array<double, kMaxLevels + 1> b{};
  std::array<double, kMaxLevels + 1> c{};
  a[0] = 1.0;
  b[0] = k_prime;
  c[0] = k;
  std::size_t levels = 0;
  while (c[levels] > kEps * a[levels] && levels < kMaxLevels) {
    a[levels + 1] = 0.5 * (a[levels] + b[levels]);
    b[levels + 1] = std::sqrt(a[levels] * b[levels]);
    // c_{n+1} = (a_n − b_n)/2 = c_n²/(4 a_{n+1}), the second form without cancellation.
    c[levels + 1] = 0.25 * c[levels] * c[levels] / a[levels + 1];
    ++levels;
  }
  // K = π/(2 a_N); reduce u to r ∈ [−K, K], r = u − 2K j.
  const double half_period = kPi / a[levels];
  const double j = std::nearbyint(u / half_period);
  const double r = u - half_period * j;
  double phi = std::ldexp(a[levels] * r, static_cast<int>(levels));  // φ_N = 2^N a_N r
  for (std::size_t n = levels; n >= 1; --n) {
    const double s = std::sin(phi);
    phi = 0.5 * (phi + std::atan2(c[n] * s, std::hypot(a[n] * std::cos(phi), b[n] * s)));
  }
  const double sign = is_odd(j) ? -1.0 : 1.0;
  const double sn = std::sin(phi);
  const double cn = std::cos(phi);
  // dn² = cn² + k'² sn² (= 1 − k² sn²), free of cancellation near k = 1.
  return {sign * sn, sign * cn, std::hypot(cn, k_prime * sn)};
}

double complete_k(double k_prime) {
  if (k_prime == 0.0) return std::numeric_limits<double>::infinity();
  return boost::math::ellint_rf(0.0, k_prime * k_prime, 1.0);
}

double incomplete_f(double sin_am, double cos_am, double k_prime) {
  const double norm = std::hypot(sin_am, cos_am);
  const double s = sin_am / norm;
  const double c = cos_am / norm;
  const double partial = s * boost::math::ellint_rf(c * c, c * c + square(k_prime * s), 1.0);
  if (c >= 0.0) return partial;
  // am ∈ (π/2, π]: F(am) = 2K − F(π − am); am ∈ (−π, −π/2): F(am) = −2K − F(−π − am).
  return std::copysign(2.0 * complete_k(k_prime), s) - partial;
}

CircularPi::CircularPi(double n, double one_minus_n, double k, double k_prime)
    : n_(n), k_complete_(complete_k(k_prime)) {
  check_modulus(k, k_prime);
  if (!(n >= 0.0) || !(one_minus_n > 0.0) || std::abs(n + one_minus_n - 1.0) > 1e-12) {
    throw std::invalid_argument("CircularPi: need 0 <= n < 1, got n = " + std::to_string(n) +
                                ", 1 - n = " + std::to_string(one_minus_n));
  }
  complete_ = k_complete_;
  if (n_ > 0.0) {
    complete_ += n_ / 3.0 * boost::math::ellint_rj(0.0, k_prime * k_prime, 1.0, one_minus_n);
  }
}

double CircularPi::operator()(double tau, const JacobiValues& f, double p) const {
  const double j = std::nearbyint(tau / (2.0 * k_complete_));
  const double s = is_odd(j) ? -f.sn : f.sn;  // sn of the reduced argument τ − 2Kj
  const double c2 = f.cn * f.cn;
  const double d2 = f.dn * f.dn;
  double value = s * boost::math::ellint_rf(c2, d2, 1.0);
  if (n_ > 0.0) value += n_ / 3.0 * s * s * s * boost::math::ellint_rj(c2, d2, 1.0, p);
  return 2.0 * j * complete_ + value;
}

ShiftedHyperbolicPi::ShiftedHyperbolicPi(double nu, double k, double k_prime)
    : nu_(nu),
      k2_(k * k),
      k_prime_(k_prime),
      weight_(nu * k_prime * k_prime / (1.0 + nu)),
      pi_((k * k + nu) / (1.0 + nu), k_prime * k_prime / (1.0 + nu), k, k_prime) {
  if (!(nu >= 0.0) || k2_ + nu_ == 0.0) {
    throw std::invalid_argument("ShiftedHyperbolicPi: need nu >= 0 and k^2 + nu > 0, got nu = " +
                                std::to_string(nu) + ", k = " + std::to_string(k));
  }
}

double ShiftedHyperbolicPi::operator()(double tau, const JacobiValues& f) const {
  const double sigma = tau - pi_.quarter_period();
  // sn, cn, dn(τ − K) = −cd τ, k' sd τ, k' nd τ.
  const double inverse_dn = 1.0 / f.dn;
  const JacobiValues shifted{-f.cn * inverse_dn, k_prime_ * f.sn * inverse_dn,
                             k_prime_ * inverse_dn};
  const double p =
      k_prime_ * k_prime_ * (1.0 + nu_ * f.sn * f.sn) / ((1.0 + nu_) * f.dn * f.dn);  // 1 − n' sn²σ
  return (k2_ * sigma + weight_ * pi_(sigma, shifted, p)) / (k2_ + nu_);
}

}  // namespace elliptic

TorqueFreeExact::TorqueFreeExact(const Eigen::Vector3d& inertia_B,
                                 const rotation::EulerParameters& theta0,
                                 const Eigen::Vector3d& w0_B)
    : regime_(TorqueFreeRegime::kSteadyRotation),
      inertia_B_(inertia_B),
      theta0_(detail::unit_euler_parameters(theta0, "TorqueFreeExact")),
      w0_B_(w0_B) {
  if (!inertia_B.allFinite() || !(inertia_B.minCoeff() > 0.0)) {
    throw std::invalid_argument("TorqueFreeExact: principal inertia must be finite and > 0");
  }
  if (!w0_B.allFinite()) {
    throw std::invalid_argument("TorqueFreeExact: initial angular velocity must be finite");
  }
  const Eigen::Vector3d m0_B = inertia_B.cwiseProduct(w0_B);
  momentum_norm_ = m0_B.norm();
  if (momentum_norm_ == 0.0 || m0_B.cross(w0_B).isZero(0.0)) return;  // permanent rotation
  const Eigen::Vector3d mu0 = m0_B / momentum_norm_;                  // m/M
  const Eigen::Vector3d& inertia = inertia_B_;

  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(),
                   [&inertia](int i, int j) { return inertia(i) < inertia(j); });
  const int i_min = order[0];
  const int i_mid = order[1];
  const int i_max = order[2];
  // (M² − 2E I_mid)/M² as the difference of two non-negative terms; its rounding error is a
  // few ε times their sum, the same size as the effect of rounding the inputs.
  const double term_max = square(mu0(i_max)) * (inertia(i_max) - inertia(i_mid)) / inertia(i_max);
  const double term_min = square(mu0(i_min)) * (inertia(i_mid) - inertia(i_min)) / inertia(i_min);
  const double delta = term_max - term_min;
  // On the separatrix only to within rounding: a looser threshold (say |k'²| < 1e-12) would be
  // wrong, since a state with k' > 0 turns back after τ ≈ 2K ≈ ln(16/k'²), while the separatrix
  // solution never does; the AGM path is accurate for any k' > 0.
  const bool separatrix = std::abs(delta) <= 8.0 * kEps * (term_max + term_min);
  if (separatrix) {
    ia_ = i_min;
    ib_ = i_mid;
    ic_ = i_max;
    const bool distinct = inertia(ia_) < inertia(ib_) && inertia(ib_) < inertia(ic_);
    if (!distinct || mu0(ia_) == 0.0 || mu0(ic_) == 0.0) return;  // permanent rotation
    regime_ = TorqueFreeRegime::kSeparatrix;
  } else if (delta > 0.0) {
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

  const double ja = inertia(ia_), jb = inertia(ib_), jc = inertia(ic_);
  const double ma = mu0(ia_), mb = mu0(ib_), mc = mu0(ic_);
  // (2E I_c − M²)/M² and (M² − 2E I_a)/M²: sums of same-sign terms in either labelling.
  const double s_ca = ma * ma * (jc - ja) / ja + mb * mb * (jc - jb) / jb;
  const double s_ac = mb * mb * (jb - ja) / jb + mc * mc * (jc - ja) / jc;
  if (s_ca == 0.0) {  // m along c to within underflow: permanent rotation
    regime_ = TorqueFreeRegime::kSteadyRotation;
    return;
  }
  const double amp_a = std::sqrt(s_ca * ja / (jc - ja));
  const double amp_b = std::sqrt(s_ca * jb / (jc - jb));
  const double amp_c = std::sqrt(s_ac * jc / (jc - ja));
  lambda_ = momentum_norm_ * std::sqrt((jc - jb) * s_ac / (ja * jb * jc));

  // Signs from ṁ_a = σ m_b m_c (1/I_c − 1/I_b), σ the parity of (a, b, c):
  // A_a λ = σ A_b A_c (I_c − I_b)/(I_b I_c).
  const double parity = (ib_ == (ia_ + 1) % 3) ? 1.0 : -1.0;
  const double sign_a = (regime_ == TorqueFreeRegime::kSeparatrix) ? std::copysign(1.0, ma) : 1.0;
  sign_c_ = std::copysign(1.0, mc);
  const double sign_b = parity * sign_a * sign_c_ * ((jc > jb) ? 1.0 : -1.0);
  amp_a_ = sign_a * amp_a;
  amp_b_ = sign_b * amp_b;
  amp_c_ = sign_c_ * amp_c;
  nu_ = (amp_a * amp_a) / (amp_c * amp_c);
  phi_rate_ = momentum_norm_ / ja;
  phi_coeff_ = (jc - ja) / (jc * lambda_);

  if (regime_ == TorqueFreeRegime::kSeparatrix) {
    k_ = 1.0;
    k_prime_ = 0.0;
    // tanh τ₀ = m_b/A_b, sech τ₀ = |(m_a, m_c)|/|(A_a, A_c)|.
    tau0_ = std::asinh(sign_b * mb * std::hypot(amp_a, amp_c) / std::hypot(ma, mc));
    h0_ = separatrix_h(tau0_);
  } else {
    const double k2 = (jb - ja) * s_ca / ((jc - jb) * s_ac);
    const double k_prime2 = (jc - ja) * delta / ((jc - jb) * s_ac);
    k_ = std::sqrt(k2);
    k_prime_ = std::sqrt(k_prime2);
    // cn τ₀ = m_a/A_a, sn τ₀ = m_b/A_b.
    tau0_ = elliptic::incomplete_f(mb / amp_b_, ma / amp_a_, k_prime_);
    phi_integral_.emplace(nu_, k_, k_prime_);
    h0_ = (*phi_integral_)(tau0_, elliptic::jacobi(tau0_, k_, k_prime_));
  }

  Eigen::Matrix3d permutation = Eigen::Matrix3d::Zero();  // body → (x, y, a) coordinates
  permutation(0, ix_) = 1.0;
  permutation(1, iy_) = 1.0;
  permutation(2, ia_) = 1.0;
  q_perm_ = rotation::euler_parameters_from_matrix(permutation).normalized();
  // R_π = A(θ₀) Pᵀ R'(0)ᵀ, with R'(0) from the same evaluation as at(0) (φ(0) = 0).
  Eigen::Vector3d w_B;
  const rotation::EulerParameters q_euler0 = euler_part(0.0, w_B);
  q_pi_ = rotation::quaternion_multiply(
              rotation::quaternion_multiply(theta0_, rotation::quaternion_conjugate(q_perm_)),
              rotation::quaternion_conjugate(q_euler0))
              .normalized();
}

double TorqueFreeExact::separatrix_h(double tau) const {
  // ∫₀^τ dτ'/(1 + ν tanh²τ') = (τ + √ν atan(√ν tanh τ))/(1 + ν).
  const double root_nu = std::sqrt(nu_);
  return (tau + root_nu * std::atan(root_nu * std::tanh(tau))) / (1.0 + nu_);
}

double TorqueFreeExact::period() const {
  if (regime_ == TorqueFreeRegime::kSteadyRotation || regime_ == TorqueFreeRegime::kSeparatrix) {
    return std::numeric_limits<double>::infinity();
  }
  return 4.0 * elliptic::complete_k(k_prime_) / lambda_;
}

RigidAttitude TorqueFreeExact::at(double t) const {
  if (regime_ == TorqueFreeRegime::kSteadyRotation) {
    return {rotation::quaternion_multiply(theta0_, rotation::exp_quaternion(w0_B_ * t)), w0_B_};
  }
  RigidAttitude result;
  const rotation::EulerParameters q_euler = euler_part(t, result.w_B);
  result.theta =
      rotation::quaternion_multiply(rotation::quaternion_multiply(q_pi_, q_euler), q_perm_);
  return result;
}

rotation::EulerParameters TorqueFreeExact::euler_part(double t, Eigen::Vector3d& w_B) const {
  const double tau = lambda_ * t + tau0_;
  elliptic::JacobiValues f{};
  double h = 0.0;
  if (regime_ == TorqueFreeRegime::kSeparatrix) {
    const double sech = 1.0 / std::cosh(tau);
    f = {std::tanh(tau), sech, sech};
    h = separatrix_h(tau);
  } else {
    f = elliptic::jacobi(tau, k_, k_prime_);
    h = (*phi_integral_)(tau, f);
  }
  Eigen::Vector3d mu;  // m_B / M
  mu(ia_) = amp_a_ * f.cn;
  mu(ib_) = amp_b_ * f.sn;
  mu(ic_) = amp_c_ * f.dn;
  w_B = momentum_norm_ * mu.cwiseQuotient(inertia_B_);
  // φ = (M/I_a)(t − (I_c − I_a)/(I_c λ) (H(τ) − H(τ₀))).
  const double phi = phi_rate_ * (t - phi_coeff_ * (h - h0_));
  // ψ = atan2(m_x, m_y), unwrapped: m_c (= m_x or m_y) never changes sign.
  const double psi = std::atan2(sign_c_ * mu(ix_), sign_c_ * mu(iy_)) + (sign_c_ < 0.0 ? kPi : 0.0);
  const double half_theta = 0.5 * std::atan2(std::hypot(mu(ix_), mu(iy_)), mu(ia_));
  return zxz_euler_parameters(phi, std::cos(half_theta), std::sin(half_theta), psi);
}

}  // namespace flexref::reference
