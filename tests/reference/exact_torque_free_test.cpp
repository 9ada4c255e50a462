#include "reference/exact_torque_free.hpp"

#include <Eigen/Geometry>
#include <array>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_3.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <boost/numeric/odeint.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "rotation/euler_parameters.hpp"
#include "tests/support/attitude_ode.hpp"
#include "tests/support/floating_point.hpp"

namespace rotation = flexref::rotation;

namespace {

namespace ref = flexref::reference;
using flexref::testing::sample_times;

using flexref::testing::kEps;

// ---- independent reference: the 7-dimensional ODE (θ, ω_B) by RKF78 ----
// State type std::vector: odeint's std::array scratch buffers trigger a spurious
// -Wuninitialized. Templated on the scalar so that the near-separatrix case can also be
// integrated in long double.
template <class Scalar>
using State = std::vector<Scalar>;

template <class Scalar>
rotation::EulerParameters theta_of(const State<Scalar>& x) {
  return rotation::EulerParameters(static_cast<double>(x[0]), static_cast<double>(x[1]),
                                   static_cast<double>(x[2]), static_cast<double>(x[3]));
}
template <class Scalar>
Eigen::Vector3d w_of(const State<Scalar>& x) {
  return Eigen::Vector3d(static_cast<double>(x[4]), static_cast<double>(x[5]),
                         static_cast<double>(x[6]));
}

/// θ̇ = ½ θ ⊗ (0, ω), J ω̇ = −ω × J ω, by RKF78 with absolute and relative tolerance `tol`.
template <class Scalar>
std::vector<State<Scalar>> integrate_torque_free(const Eigen::Vector3d& inertia,
                                                 const rotation::EulerParameters& theta0,
                                                 const Eigen::Vector3d& w0,
                                                 const std::vector<double>& times, Scalar tol) {
  namespace odeint = boost::numeric::odeint;
  const std::array<Scalar, 3> j{inertia(0), inertia(1), inertia(2)};
  const auto rhs = [&j](const State<Scalar>& x, State<Scalar>& dxdt, Scalar) {
    const Scalar e0 = x[0], e1 = x[1], e2 = x[2], e3 = x[3];
    const Scalar w1 = x[4], w2 = x[5], w3 = x[6];
    dxdt[0] = -Scalar(0.5) * (e1 * w1 + e2 * w2 + e3 * w3);  // θ̇ = ½ θ ⊗ (0, ω)
    dxdt[1] = Scalar(0.5) * (e0 * w1 + e2 * w3 - e3 * w2);
    dxdt[2] = Scalar(0.5) * (e0 * w2 + e3 * w1 - e1 * w3);
    dxdt[3] = Scalar(0.5) * (e0 * w3 + e1 * w2 - e2 * w1);
    dxdt[4] = (j[1] - j[2]) * w2 * w3 / j[0];  // Euler's equations
    dxdt[5] = (j[2] - j[0]) * w3 * w1 / j[1];
    dxdt[6] = (j[0] - j[1]) * w1 * w2 / j[2];
  };
  using Stepper = odeint::controlled_runge_kutta<
      odeint::runge_kutta_fehlberg78<State<Scalar>, Scalar, State<Scalar>, Scalar>>;
  std::vector<Scalar> scalar_times(times.begin(), times.end());
  std::vector<State<Scalar>> out;
  State<Scalar> x{theta0(0), theta0(1), theta0(2), theta0(3), w0(0), w0(1), w0(2)};
  odeint::integrate_times(Stepper(typename Stepper::error_checker_type(tol, tol)), rhs, x,
                          scalar_times.begin(), scalar_times.end(), Scalar(1e-3),
                          [&out](const State<Scalar>& s, Scalar) { out.push_back(s); });
  return out;
}

struct Case {
  std::string name;
  Eigen::Vector3d inertia;
  rotation::EulerParameters theta0;
  Eigen::Vector3d w0;
  double t_end;          ///< span of the exact-solution checks
  double t_end_numeric;  ///< span of the RKF78 comparison
  ref::TorqueFreeRegime regime;
};

rotation::EulerParameters tilted() {
  return rotation::exp_quaternion(Eigen::Vector3d(0.3, -0.7, 1.1));
}

std::vector<Case> cases() {
  using R = ref::TorqueFreeRegime;
  return {
      // free_spin scene: circulation about the max-inertia axis.
      {"free_spin",
       {3.0, 4.0, 5.0},
       rotation::identity_euler_parameters(),
       {0.2, 0.3, 2.0},
       100.0,
       100.0,
       R::kCirculationMaxAxis},
      // Book toss after the kick, k'² ≈ 7e-9 (M² − 2E I₂ = 1.2e-6 against M² = 400). The
      // flip times depend on k' like ln(1/k'), so a drift η of the invariants in a numerical
      // solution shifts them by ~η/(M² − 2E I₂)·M² ≈ 3e8 η: double-precision RKF78 at 1e-13 is
      // off by 2e-6 at t = 100 (by 2e-9 at tolerance 1e-17 in long double), while the exact
      // solution agrees with a float128 RKF78 run (tolerance 1e-24) to 8e-14 in ω and 3e-13 rad
      // over [0, 100]. The RKF78 comparison therefore covers the scene's span, [0, 10].
      {"book_toss_near_separatrix",
       {1.0, 2.0, 2.8},
       rotation::identity_euler_parameters(),
       {1e-3, 10.0, 1e-3},
       100.0,
       10.0,
       R::kCirculationMaxAxis},
      // circulation about the min-inertia axis, inertia in a non-sorted order, tilted start.
      {"min_axis_unsorted",
       {2.0, 1.0, 3.0},
       tilted(),
       {0.3, 2.0, -0.4},
       50.0,
       50.0,
       R::kCirculationMinAxis},
      // symmetric (oblate) body: regular precession, k = 0.
      {"symmetric_oblate",
       {2.0, 3.0, 2.0},
       tilted(),
       {0.5, 1.5, -0.2},
       50.0,
       50.0,
       R::kCirculationMaxAxis},
      // symmetric (prolate) body.
      {"symmetric_prolate",
       {1.0, 2.5, 2.5},
       tilted(),
       {1.5, 0.4, 0.3},
       50.0,
       50.0,
       R::kCirculationMinAxis},
  };
}

/// Largest |ω|; every rate in the problem scales with it.
double rate_scale(const ref::TorqueFreeExact& exact, const std::vector<double>& times) {
  double omega = 0.0;
  for (double t : times) omega = std::max(omega, exact.at(t).w_B.norm());
  return omega;
}

/// Largest ω error relative to Ω and largest geodesic angle between exact and numerical.
template <class Scalar>
std::pair<double, double> worst_difference(const ref::TorqueFreeExact& exact,
                                           const std::vector<double>& times,
                                           const std::vector<State<Scalar>>& numeric) {
  REQUIRE(numeric.size() == times.size());
  const double omega = rate_scale(exact, times);
  double worst_w = 0.0;
  double worst_angle = 0.0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const ref::RigidAttitude s = exact.at(times[i]);
    worst_w = std::max(worst_w, (s.w_B - w_of(numeric[i])).norm() / omega);
    worst_angle = std::max(worst_angle, rotation::geodesic_angle(s.theta, theta_of(numeric[i])));
  }
  return {worst_w, worst_angle};
}

}  // namespace

TEST_CASE("elliptic helpers agree with Boost.Math where Boost is accurate",
          "[reference][exact_torque_free][elliptic]") {
  for (double k : {0.0, 0.1, 0.5, 0.9}) {
    const double k_prime = std::sqrt((1.0 - k) * (1.0 + k));
    for (double u = -20.0; u <= 20.0; u += 0.731) {
      double cn = 0.0, dn = 0.0;
      const double sn = boost::math::jacobi_elliptic(k, u, &cn, &dn);
      const ref::elliptic::JacobiValues f = ref::elliptic::jacobi(u, k, k_prime);
      CAPTURE(k, u, sn, f.sn, cn, f.cn, dn, f.dn);
      // Both are AGM evaluations; Boost does not reduce the argument, so its absolute error
      // grows like ε·|u|·(few): 1e-13 covers |u| ≤ 20 with a factor ~20 margin.
      CHECK(std::abs(f.sn - sn) <= 1e-13);
      CHECK(std::abs(f.cn - cn) <= 1e-13);
      CHECK(std::abs(f.dn - dn) <= 1e-13);
    }
    // K and the inverse F(am) round-trip. Carlson's R_F is accurate to a few ε.
    CHECK(std::abs(ref::elliptic::complete_k(k_prime) - boost::math::ellint_1(k)) <= 4 * kEps);
    for (double am = -3.0; am <= 3.0; am += 0.25) {
      const double u = ref::elliptic::incomplete_f(std::sin(am), std::cos(am), k_prime);
      const ref::elliptic::JacobiValues f = ref::elliptic::jacobi(u, k, k_prime);
      CAPTURE(k, am, u);
      CHECK(std::abs(std::atan2(f.sn, f.cn) - am) <= 16 * kEps);  // well-conditioned: dF/dam ≤ 1/k'
    }
  }
}

TEST_CASE("elliptic helpers stay accurate near k = 1 where Boost loses k'",
          "[reference][exact_torque_free][elliptic]") {
  // A&S 16.15: sn = tanh u + ¼k'²(sinh u cosh u − u) sech²u + O(k'⁴) etc.; with k' = 1e-5 the
  // neglected O(k'⁴ e^{4u}) terms are below 1e-18 for |u| ≤ 2.
  const double k_prime = 1e-5;
  const double k = std::sqrt((1.0 - k_prime) * (1.0 + k_prime));
  const double m1 = k_prime * k_prime;
  for (double u = -2.0; u <= 2.0; u += 0.173) {
    const double sech = 1.0 / std::cosh(u);
    const double sc = std::sinh(u) * std::cosh(u);
    const double sn = std::tanh(u) + 0.25 * m1 * (sc - u) * sech * sech;
    const double cn = sech - 0.25 * m1 * (sc - u) * std::tanh(u) * sech;
    const double dn = sech + 0.25 * m1 * (sc + u) * std::tanh(u) * sech;
    const ref::elliptic::JacobiValues f = ref::elliptic::jacobi(u, k, k_prime);
    CAPTURE(u, sn, f.sn, cn, f.cn, dn, f.dn);
    CHECK(std::abs(f.sn - sn) <= 1e-14);  // a few ε from the AGM, 4ε from the expansion
    CHECK(std::abs(f.cn - cn) <= 1e-14);
    CHECK(std::abs(f.dn - dn) <= 1e-14);
  }
  // K = ln(4/k') + O(k'² ln k'): the complement carries K to full precision, while Boost's
  // ellint_1(k) has to recover k' from k and is off by about ε/k'² relative in k'.
  const double asymptotic = std::log(4.0 / k_prime) + 0.25 * m1 * (std::log(4.0 / k_prime) - 1.0);
  CHECK(std::abs(ref::elliptic::complete_k(k_prime) - asymptotic) <= 1e-14);
}

TEST_CASE("elliptic Pi forms agree with Boost ellint_3 and with quadrature",
          "[reference][exact_torque_free][elliptic]") {
  for (double k : {0.2, 0.8}) {
    const double k_prime = std::sqrt((1.0 - k) * (1.0 + k));
    const double quarter = ref::elliptic::complete_k(k_prime);
    for (double n : {0.0, 0.3, 0.95}) {
      const ref::elliptic::CircularPi pi(n, 1.0 - n, k, k_prime);
      for (double u = -9.0; u <= 9.0; u += 0.61) {
        const ref::elliptic::JacobiValues f = ref::elliptic::jacobi(u, k, k_prime);
        const double j = std::nearbyint(u / (2.0 * quarter));
        const double sign = std::fmod(j, 2.0) != 0.0 ? -1.0 : 1.0;
        const double amplitude = std::atan2(sign * f.sn, sign * f.cn) + j * M_PI;
        const double expected = boost::math::ellint_3(k, n, amplitude);
        CAPTURE(k, n, u, expected);
        // Boost's Π with |φ| > π/2 uses the same quasi-periodicity; relative few ε.
        CHECK(std::abs(pi(u, f, 1.0 - n * f.sn * f.sn) - expected) <=
              64 * kEps * std::abs(expected) + 1e-15);
      }
    }
  }
  // The shifted hyperbolic form against adaptive Gauss–Kronrod, including ν = 1e8 where
  // Carlson's direct form would cancel to ~1e-8 relative.
  for (double k : {0.0, 0.6, 0.99999}) {
    const double k_prime = std::sqrt((1.0 - k) * (1.0 + k));
    const double quarter = ref::elliptic::complete_k(k_prime);
    for (double nu : {1e-3, 1.0, 1e8}) {
      const ref::elliptic::ShiftedHyperbolicPi h(nu, k, k_prime);
      const auto integrand = [&](double x) {
        const double sn = ref::elliptic::jacobi(x, k, k_prime).sn;
        return 1.0 / (1.0 + nu * sn * sn);
      };
      for (double u : {-3.3, -1.0, 0.2, 2.9}) {
        double error_estimate = 0.0;
        const double expected = boost::math::quadrature::gauss_kronrod<double, 61>::integrate(
            integrand, quarter, u, 12, 1e-14, &error_estimate);
        CAPTURE(k, nu, u, expected, error_estimate);
        CHECK(std::abs(h(u, ref::elliptic::jacobi(u, k, k_prime)) - expected) <=
              1e-14 * std::max(1.0, std::abs(expected)) + error_estimate);
      }
    }
  }
}

TEST_CASE("TorqueFreeExact reproduces the initial state and classifies the regime",
          "[reference][exact_torque_free]") {
  for (const Case& c : cases()) {
    const ref::TorqueFreeExact exact(c.inertia, c.theta0, c.w0);
    const ref::RigidAttitude s0 = exact.at(0.0);
    CAPTURE(c.name, s0.w_B, c.w0, s0.theta, c.theta0);
    CHECK(exact.regime() == c.regime);
    // ω from sn, cn, dn of F(am₀): a few ε relative; θ(0) = R_π R'(0) P: a few ε.
    CHECK((s0.w_B - c.w0).norm() <= 16 * kEps * c.w0.norm());
    CHECK(rotation::geodesic_angle(s0.theta, c.theta0) <= 16 * kEps);
    CHECK((s0.theta - c.theta0).norm() <= 16 * kEps);  // same sign, not only same rotation
  }
}

TEST_CASE("TorqueFreeExact satisfies Euler's equations and the attitude kinematics",
          "[reference][exact_torque_free]") {
  for (const Case& c : cases()) {
    const ref::TorqueFreeExact exact(c.inertia, c.theta0, c.w0);
    const std::vector<double> times = sample_times(c.t_end, 41);
    const double omega = rate_scale(exact, times);
    // Step h = 1e-4/Ω. Truncation h²/6·|d³x/dt³|: Euler's coefficients (I_j − I_k)/I_i are ≤ 1
    // in magnitude (triangle inequality), so |d³ω/dt³| ≤ 6Ω⁴ and |d³θ/dt³| ≤ 6Ω³: ≤ 1e-8 Ω²
    // resp. Ω. Round-off: τ = λt + τ₀ and φ carry ~ε·Ωt ≤ 2.2e-13 (Ωt ≤ 1000), over 2h:
    // ≤ 1.1e-9 Ω(²). Sum ≤ 1.2e-8; bound 1e-7 (measured ≤ 3e-10 for ω, ≤ 1.3e-9 for θ).
    const double h = 1e-4 / omega;
    for (double t : times) {
      const double tc = std::max(t, h);
      const ref::RigidAttitude s = exact.at(tc);
      const ref::RigidAttitude plus = exact.at(tc + h);
      const ref::RigidAttitude minus = exact.at(tc - h);
      const Eigen::Vector3d w_rate_fd = (plus.w_B - minus.w_B) / (2.0 * h);
      const Eigen::Vector3d w_rate =
          (-s.w_B.cross(c.inertia.cwiseProduct(s.w_B))).cwiseQuotient(c.inertia);
      const rotation::EulerParameters theta_rate_fd = (plus.theta - minus.theta) / (2.0 * h);
      const rotation::EulerParameters theta_rate = rotation::euler_parameter_rate(s.theta, s.w_B);
      CAPTURE(c.name, tc, w_rate_fd, w_rate, theta_rate_fd, theta_rate);
      CHECK((w_rate_fd - w_rate).norm() <= 1e-7 * omega * omega);
      CHECK((theta_rate_fd - theta_rate).norm() <= 1e-7 * omega);
      CHECK(std::abs(s.theta.norm() - 1.0) <= 8 * kEps);
    }
  }
}

TEST_CASE("TorqueFreeExact conserves energy and the global angular momentum",
          "[reference][exact_torque_free]") {
  for (const Case& c : cases()) {
    const ref::TorqueFreeExact exact(c.inertia, c.theta0, c.w0);
    const double energy0 = 0.5 * c.w0.dot(c.inertia.cwiseProduct(c.w0));
    const Eigen::Vector3d pi0 = rotation::rotation_matrix(c.theta0) * c.inertia.cwiseProduct(c.w0);
    for (double t : sample_times(c.t_end, 97)) {
      const ref::RigidAttitude s = exact.at(t);
      const double energy = 0.5 * s.w_B.dot(c.inertia.cwiseProduct(s.w_B));
      const Eigen::Vector3d pi = rotation::rotation_matrix(s.theta) * c.inertia.cwiseProduct(s.w_B);
      CAPTURE(c.name, t, energy, energy0, pi, pi0);
      // ω_B is evaluated to a few ε relative, so E to ~10ε relative.
      CHECK(std::abs(energy - energy0) <= 32 * kEps * energy0);
      // |π| from ω alone: few ε. Global π also rotates with the attitude, whose absolute error
      // is ~ε·(M t/I_a) ≤ ε·1000 here: 1e-12 relative.
      CHECK(std::abs(pi.norm() - pi0.norm()) <= 32 * kEps * pi0.norm());
      CHECK((pi - pi0).norm() <= 1e-12 * pi0.norm());
    }
  }
}

TEST_CASE("TorqueFreeExact agrees with RKF78 at tolerance 1e-13",
          "[reference][exact_torque_free][odeint]") {
  for (const Case& c : cases()) {
    const ref::TorqueFreeExact exact(c.inertia, c.theta0, c.w0);
    const std::vector<double> times = sample_times(c.t_end_numeric, 200);
    CAPTURE(c.name);
    if (c.name == "book_toss_near_separatrix") {
      // During a flip ω turns at λ|ω| ≈ 50 rad/s², so a shift δt of the flip times shows as
      // δω/|ω| ≈ λ δt. The flip times depend on the invariants through K ≈ ln(4/k') with
      // k'² ∝ M² − 2E I₂ = 3e-9 M², so RKF78's round-off drift of the invariants is amplified
      // ~3e8-fold: in double it is 4e-8 … 2e-7 depending on how the right-hand side rounds,
      // which tests nothing. Long double (ε = 1.1e-19) at tolerance 1e-17 brings it to 5e-11;
      // the brief's 1e-9 leaves a margin of 20. (A float128 RKF78 run at tolerance 1e-24 agrees
      // with the exact solution to 1.1e-13 in ω and 4e-13 rad over [0, 100].)
      const auto [worst_w, worst_angle] = worst_difference(
          exact, times,
          integrate_torque_free<long double>(c.inertia, c.theta0, c.w0, times, 1e-17L));
      CAPTURE(worst_w, worst_angle);
      CHECK(worst_w <= 1e-9);
      CHECK(worst_angle <= 1e-9);
    } else {
      // RKF78 at local tolerance 1e-13 over ≤ 1000 rad of rotation: global error ≲ 1e-11
      // (measured ≤ 3e-13 in ω, ≤ 9e-12 rad); the exact solution is ~1e-13. Bound 1e-9.
      const auto [worst_w, worst_angle] = worst_difference(
          exact, times, integrate_torque_free(c.inertia, c.theta0, c.w0, times, 1e-13));
      CAPTURE(worst_w, worst_angle);
      CHECK(worst_w <= 1e-9);
      CHECK(worst_angle <= 1e-9);
    }
  }
}

TEST_CASE("TorqueFreeExact is periodic in the body and precesses regularly when symmetric",
          "[reference][exact_torque_free]") {
  for (const Case& c : cases()) {
    const ref::TorqueFreeExact exact(c.inertia, c.theta0, c.w0);
    const double period = exact.period();
    REQUIRE(std::isfinite(period));
    for (double t : {0.0, 0.37, 1.9}) {
      CAPTURE(c.name, t, period);
      // ω(t + T) = ω(t): K and λ to a few ε, phase error ~ε(λT) → ~1e-14·Ω.
      CHECK((exact.at(t + period).w_B - exact.at(t).w_B).norm() <= 1e-13 * c.w0.norm());
    }
  }
  // Oblate symmetric body, axis c = body y (I = 3), I⊥ = 2: ω_c constant, the transverse ω
  // turns about the symmetry axis at (I_c − I⊥)/I⊥ ω_c in the body, and the symmetry axis
  // precesses about π at |π|/I⊥ at a constant angle (Landau–Lifshitz §33).
  const Eigen::Vector3d inertia(2.0, 3.0, 2.0);
  const Eigen::Vector3d w0(0.5, 1.5, -0.2);
  const ref::TorqueFreeExact exact(inertia, tilted(), w0);
  CHECK(exact.modulus() == 0.0);
  const Eigen::Vector3d pi = rotation::rotation_matrix(tilted()) * inertia.cwiseProduct(w0);
  const Eigen::Vector3d axis0 = rotation::rotation_matrix(tilted()) * Eigen::Vector3d::UnitY();
  const double body_rate = (3.0 - 2.0) / 2.0 * w0(1);
  const double precession_rate = pi.norm() / 2.0;
  for (double t = 0.0; t <= 40.0; t += 1.3) {
    const ref::RigidAttitude s = exact.at(t);
    const Eigen::Vector3d w_expected =
        Eigen::AngleAxisd(body_rate * t, Eigen::Vector3d::UnitY()) * w0;
    const Eigen::Vector3d axis_expected =
        Eigen::AngleAxisd(precession_rate * t, pi.normalized()) * axis0;
    const Eigen::Vector3d axis = rotation::rotation_matrix(s.theta) * Eigen::Vector3d::UnitY();
    CAPTURE(t, s.w_B, w_expected, axis, axis_expected);
    // Elementary closed forms; both sides accurate to ~ε·(rate·t) ≤ ε·60.
    CHECK((s.w_B - w_expected).norm() <= 1e-13);
    CHECK((axis - axis_expected).norm() <= 1e-13);
  }
}

TEST_CASE("TorqueFreeExact on the separatrix", "[reference][exact_torque_free][odeint]") {
  // 2E I₂ = |π|² exactly (also in floating point) for J = diag(3, 4, 6), ω = (2, 1, 1)
  // (m₃²(I₃ − I₂)/I₃ = m₁²(I₂ − I₁)/I₁ = 12), and to rounding for J = diag(1, 2, 3),
  // ω = (±√3, ±0.5, 1) (m₃²/3 = m₁²).
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> states = {
      {{3.0, 4.0, 6.0}, {2.0, 1.0, 1.0}},
      {{1.0, 2.0, 3.0}, {std::sqrt(3.0), 0.5, 1.0}},
      {{1.0, 2.0, 3.0}, {-std::sqrt(3.0), -0.5, 1.0}}};
  for (const auto& [inertia, w0] : states) {
    const ref::TorqueFreeExact exact(inertia, tilted(), w0);
    REQUIRE(exact.regime() == ref::TorqueFreeRegime::kSeparatrix);
    const double momentum = inertia.cwiseProduct(w0).norm();
    const double two_energy = w0.dot(inertia.cwiseProduct(w0));
    // λ = √((I₃ − I₂)(M² − 2E I₁)/(I₁I₂I₃)); the asymptotic approach to the middle axis
    // amplifies any perturbation like e^{λt}, so compare with RKF78 while e^{λt}·1e-13 ≲ 1e-10:
    // λ t_end = 7 (e⁷ ≈ 1100).
    const double lambda =
        std::sqrt((inertia(2) - inertia(1)) * (momentum * momentum - two_energy * inertia(0)) /
                  (inertia(0) * inertia(1) * inertia(2)));
    const double t_end = 7.0 / lambda;
    const std::vector<double> times = sample_times(t_end, 60);
    const std::vector<State<double>> numeric =
        integrate_torque_free(inertia, tilted(), w0, times, 1e-13);
    for (std::size_t i = 0; i < times.size(); ++i) {
      const ref::RigidAttitude s = exact.at(times[i]);
      CAPTURE(inertia, w0, times[i], s.w_B, w_of(numeric[i]));
      CHECK((s.w_B - w_of(numeric[i])).norm() <= 1e-9 * w0.norm());
      CHECK(rotation::geodesic_angle(s.theta, theta_of(numeric[i])) <= 1e-9);
    }
    // Asymptotically ω → rotation about the middle axis with |m| = M: ω₂ → ±M/I₂. At λt = 60
    // tanh = 1 and sech = 9e-27 in double, and |A_b| = M to a few ε: bound 16ε·M/I₂. (This
    // checks the separatrix solution itself; the √3 states, 1e-16 off the separatrix, would
    // physically turn back after τ ≈ ln(16/k'²) ≈ 40.)
    const ref::RigidAttitude late = exact.at(60.0 / lambda);
    CHECK(std::abs(std::abs(late.w_B(1)) - momentum / inertia(1)) <=
          16 * kEps * momentum / inertia(1));
    // Euler's equations hold on the separatrix as well (same finite-difference bound as above).
    const double omega = w0.norm();
    const double h = 1e-4 / omega;
    for (double t : times) {
      const double tc = std::max(t, h);
      const ref::RigidAttitude s = exact.at(tc);
      const Eigen::Vector3d w_rate_fd = (exact.at(tc + h).w_B - exact.at(tc - h).w_B) / (2.0 * h);
      const Eigen::Vector3d w_rate =
          (-s.w_B.cross(inertia.cwiseProduct(s.w_B))).cwiseQuotient(inertia);
      const rotation::EulerParameters theta_rate_fd =
          (exact.at(tc + h).theta - exact.at(tc - h).theta) / (2.0 * h);
      CAPTURE(tc, w_rate_fd, w_rate);
      CHECK((w_rate_fd - w_rate).norm() <= 1e-7 * omega * omega);
      CHECK((theta_rate_fd - rotation::euler_parameter_rate(s.theta, s.w_B)).norm() <=
            1e-7 * omega);
    }
  }
}

TEST_CASE("TorqueFreeExact permanent rotations", "[reference][exact_torque_free]") {
  // About a principal axis (including the unstable middle one), in the isotropic plane of a
  // symmetric body, at rest, and for a sphere: θ(t) = θ₀ ⊗ exp(ω₀ t) exactly.
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> states = {
      {{1.0, 2.0, 3.0}, {0.0, 2.0, 0.0}},
      {{1.0, 2.0, 3.0}, {0.0, 0.0, -1.5}},
      {{2.0, 2.0, 3.0}, {0.7, -0.4, 0.0}},
      {{1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}},
      {{2.0, 2.0, 2.0}, {0.3, 0.2, 0.1}}};
  for (const auto& [inertia, w0] : states) {
    const ref::TorqueFreeExact exact(inertia, tilted(), w0);
    CHECK(exact.regime() == ref::TorqueFreeRegime::kSteadyRotation);
    for (double t : {0.0, 1.0, 17.3}) {
      const ref::RigidAttitude s = exact.at(t);
      CHECK(s.w_B == w0);
      // The same formula with θ₀ normalised once more: equal to a few ε.
      CHECK(rotation::geodesic_angle(s.theta, rotation::quaternion_multiply(
                                                  tilted(), rotation::exp_quaternion(w0 * t))) <=
            4 * kEps);
    }
  }
}

TEST_CASE("TorqueFreeExact rejects invalid input", "[reference][exact_torque_free]") {
  const rotation::EulerParameters identity = rotation::identity_euler_parameters();
  const Eigen::Vector3d w0(0.1, 0.2, 0.3);
  CHECK_THROWS_AS(ref::TorqueFreeExact({0.0, 1.0, 2.0}, identity, w0), std::invalid_argument);
  CHECK_THROWS_AS(ref::TorqueFreeExact({1.0, -1.0, 2.0}, identity, w0), std::invalid_argument);
  CHECK_THROWS_AS(ref::TorqueFreeExact({1.0, std::nan(""), 2.0}, identity, w0),
                  std::invalid_argument);
  CHECK_THROWS_AS(
      ref::TorqueFreeExact({1.0, 2.0, 3.0}, rotation::EulerParameters(1.0, 0.1, 0.0, 0.0), w0),
      std::invalid_argument);
  CHECK_THROWS_AS(ref::TorqueFreeExact({1.0, 2.0, 3.0}, identity, {0.0, INFINITY, 0.0}),
                  std::invalid_argument);
  CHECK_THROWS_AS(ref::elliptic::jacobi(0.3, 0.5, 0.5), std::invalid_argument);
}
