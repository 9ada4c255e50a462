/// Property tests for core/euler_parameters against docs/design/model.md "Kinematics": A(θ), Ḡ, G,
/// the velocity relations ω̄ = 2Ḡθ̇, ω = 2Gθ̇ = Aω̄, θ̇ = ½Ḡᵀω̄ = ½θ⊗(0, ω̄), Ḡ(θ̇)θ̇ = 0,
/// the quaternion exp/log against core/so3, Shepperd's conversion and the geodesic angle.
#include "rotation/euler_parameters.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "rotation/so3.hpp"
#include "tests/support/finite_difference.hpp"
#include "tests/support/floating_point.hpp"
#include "tests/support/matrix_checks.hpp"
#include "tests/support/rotation_samples.hpp"

namespace flexref::core {
namespace {

using flexref::testing::central_difference_jacobian;
using flexref::testing::max_relative_difference;

using flexref::testing::check_close;
using flexref::testing::flatten;
using flexref::testing::kEps;
using flexref::testing::kPi;
using flexref::testing::unflatten;
// exp_quaternion switches to its Taylor series for |φ|/2 < 1e-2, i.e. |φ| < 2e-2.
constexpr double kQuaternionBranchAngle = 2e-2;
// Central differences with h = ε^(1/3)·max(1, |t|) ≈ 6e-6: truncation h²/6·|f'''| ≲ 1e-11 for
// the O(1) rates used here, round-off ε/h ≈ 4e-11; agreement to ~1e-10, and 1e-8 leaves 100×.
constexpr double kFiniteDifferenceTolerance = 1e-8;

using flexref::testing::generic_axis;
using flexref::testing::RotationSample;

/// Rotation vectors at 0, 1e-8, both sides of exp_quaternion's branch switch, generic (fixed
/// seed) and near π.
std::vector<RotationSample> quaternion_branch_samples() {
  return flexref::testing::rotation_vector_samples({1e-2, kQuaternionBranchAngle}, 20240612u);
}

struct AttitudeSample {
  std::string name;
  rotation::EulerParameters theta;
};

/// Unit Euler parameters in both hemispheres: θ = exp_quaternion(φ) for every rotation-vector
/// sample, and −θ (same attitude, e0 ≤ 0).
std::vector<AttitudeSample> attitude_samples() {
  std::vector<AttitudeSample> samples;
  for (const RotationSample& s : quaternion_branch_samples()) {
    const rotation::EulerParameters theta = rotation::exp_quaternion(s.phi);
    samples.push_back({s.name, theta});
    samples.push_back({"minus " + s.name, -theta});
  }
  return samples;
}

rotation::EulerParameters random_unit_quaternion(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return rotation::EulerParameters(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
}

rotation::EulerParameters pure_quaternion(const Eigen::Vector3d& v) {
  return rotation::EulerParameters(0.0, v.x(), v.y(), v.z());
}

/// d/dt f(t) at t by central differences (tests/support helper).
Eigen::VectorXd time_derivative(const std::function<Eigen::VectorXd(double)>& f, double t) {
  return central_difference_jacobian([&f](const Eigen::VectorXd& x) { return f(x(0)); },
                                     Eigen::VectorXd::Constant(1, t))
      .col(0);
}

TEST_CASE("rotation_matrix follows model.md and Eigen's Hamilton convention", "[euler]") {
  // Sign convention pinned: θ = (cos 45°, 0, 0, sin 45°) is a quarter turn about z (body →
  // global), so A e_x = e_y. Entries are cos²−sin² etc. of O(1) values: 4ε.
  const double c = std::cos(0.25 * kPi);
  const double s = std::sin(0.25 * kPi);
  check_close(rotation::rotation_matrix(rotation::EulerParameters(c, 0.0, 0.0, s)) *
                  Eigen::Vector3d::UnitX(),
              Eigen::Vector3d::UnitY(), 4.0 * kEps);
  CHECK(rotation::rotation_matrix(rotation::identity_euler_parameters()) ==
        Eigen::Matrix3d::Identity());
  std::vector<AttitudeSample> samples = attitude_samples();
  std::mt19937 rng(3);
  for (int i = 0; i < 20; ++i) samples.push_back({"random", random_unit_quaternion(rng)});
  for (const AttitudeSample& sample : samples) {
    INFO(sample.name << ", theta = " << sample.theta.transpose());
    const Eigen::Matrix3d a = rotation::rotation_matrix(sample.theta);
    // Every entry is a sum of ≤ 4 products of O(1) values: ≲ 3 ulp; AᵀA sums three products
    // of such entries, and θᵀθ − 1 = O(ε) enters as (θᵀθ)² − 1: ≲ 12ε. Use 16ε ≈ 3.6e-15.
    check_close(a.transpose() * a, Eigen::Matrix3d::Identity(), 16.0 * kEps);
    check_close(a.determinant(), 1.0, 16.0 * kEps);
    // Every term of A is quadratic in θ and negation is exact: bitwise A(θ) = A(−θ).
    CHECK(rotation::rotation_matrix(-sample.theta) == a);
    // Eigen's quaternion (Hamilton, w first in the constructor) uses 1 − 2(y² + z²) etc.:
    // equal for unit θ up to a few ulp each, 16ε.
    const Eigen::Quaterniond eigen_q(sample.theta(0), sample.theta(1), sample.theta(2),
                                     sample.theta(3));
    check_close(a, eigen_q.toRotationMatrix(), 16.0 * kEps);
  }
}

TEST_CASE("rotation_matrix<long double> is a rotation and agrees with the double one", "[euler]") {
  using Quaternion = Eigen::Matrix<long double, 4, 1>;
  using Matrix3 = Eigen::Matrix<long double, 3, 3>;
  constexpr long double kEpsExtended = std::numeric_limits<long double>::epsilon();
  const auto max_abs = [](const Matrix3& m) { return m.cwiseAbs().maxCoeff(); };
  std::vector<AttitudeSample> samples = attitude_samples();
  std::mt19937 rng(5);
  for (int i = 0; i < 20; ++i) samples.push_back({"random", random_unit_quaternion(rng)});
  for (const AttitudeSample& sample : samples) {
    INFO(sample.name << ", theta = " << sample.theta.transpose());
    // θ unit to the extended ε: the double θ cast, normalized in long double.
    const Quaternion theta = sample.theta.cast<long double>().normalized();
    const Matrix3 a = rotation::rotation_matrix<long double>(theta);
    // The double case's bound in the extended ε (entries ≲ 3 ulp, AᵀA sums three products,
    // θᵀθ − 1 ≲ 2ε): 16ε_ext ≈ 1.7e-18.
    CHECK(max_abs(a.transpose() * a - Matrix3::Identity()) <= 16.0L * kEpsExtended);
    CHECK(std::abs(a.determinant() - 1.0L) <= 16.0L * kEpsExtended);
    // Against A in double of the same double θ: the long double entries of that θ carry the
    // double roundings only, each entry a sum of ≤ 3 rounded operations on values ≤ 2 in
    // magnitude (2e0², −1, +2e_i²), ≲ 3 ulp of 1; plus |θ_double|² − 1 ≲ 2ε entering linearly
    // through the normalization in long double: ≲ 5ε ≈ 1.1e-15, 8ε leaves margin. (1e-16 is
    // below one ulp of an O(1) double entry, so no double A can meet it.)
    const Matrix3 a_double = rotation::rotation_matrix(sample.theta).cast<long double>();
    CHECK(max_abs(a - a_double) <= 8.0L * static_cast<long double>(kEps));
  }
}

TEST_CASE("rotation_matrix_of_any_norm is A of the normalized parameters", "[euler]") {
  using Quaternion = Eigen::Matrix<long double, 4, 1>;
  using Matrix3 = Eigen::Matrix<long double, 3, 3>;
  constexpr long double kEpsExtended = std::numeric_limits<long double>::epsilon();
  const auto max_abs = [](const Matrix3& m) { return m.cwiseAbs().maxCoeff(); };
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> scale(0.25, 4.0);
  for (int i = 0; i < 40; ++i) {
    const rotation::EulerParameters unit = random_unit_quaternion(rng);
    const Quaternion theta = unit.cast<long double>() * static_cast<long double>(scale(rng));
    INFO("theta = " << unit.transpose() << ", |theta| = " << static_cast<double>(theta.norm()));
    const Matrix3 a = rotation::rotation_matrix_of_any_norm<long double>(theta);
    // Entries 1 − s(e_i² + e_j²) and s(e_i e_j ± e0 e_k) with s = 2/|θ|²: ≲ 4 roundings of O(1)
    // values each, and the normalized θ of the reference ≲ 2ε: 16ε_ext.
    CHECK(max_abs(a - rotation::rotation_matrix<long double>(theta.normalized())) <=
          16.0L * kEpsExtended);
    CHECK(max_abs(a.transpose() * a - Matrix3::Identity()) <= 16.0L * kEpsExtended);
    // In double on a unit θ: the same map with other roundings, 16ε as for A against Eigen's.
    check_close(rotation::rotation_matrix_of_any_norm<double>(unit),
                rotation::rotation_matrix(unit), 16.0 * kEps);
  }
}

TEST_CASE("G and G-bar satisfy the identities of model.md", "[euler]") {
  std::vector<AttitudeSample> samples = attitude_samples();
  std::mt19937 rng(4);
  for (int i = 0; i < 20; ++i) samples.push_back({"random", random_unit_quaternion(rng)});
  for (const AttitudeSample& sample : samples) {
    INFO(sample.name << ", theta = " << sample.theta.transpose());
    const rotation::EulerParameters& theta = sample.theta;
    const double e0 = theta(0);
    const Eigen::Vector3d e = theta.tail<3>();
    const rotation::Matrix34d g_bar = rotation::g_bar_matrix(theta);
    const rotation::Matrix34d g = rotation::g_matrix(theta);
    // The block forms Ḡ = [−e, e0 I − ẽ], G = [−e, e0 I + ẽ]: every entry is ±e_i exactly.
    rotation::Matrix34d g_bar_expected;
    g_bar_expected << -e, e0 * Eigen::Matrix3d::Identity() - rotation::hat(e);
    rotation::Matrix34d g_expected;
    g_expected << -e, e0 * Eigen::Matrix3d::Identity() + rotation::hat(e);
    CHECK(g_bar == g_bar_expected);
    CHECK(g == g_expected);
    // Ḡθ = Gθ = 0: four products that cancel in pairs, ≲ 2 ulp of O(1) → 4ε.
    check_close(g_bar * theta, Eigen::Vector3d::Zero(), 4.0 * kEps);
    check_close(g * theta, Eigen::Vector3d::Zero(), 4.0 * kEps);
    // ḠḠᵀ = GGᵀ = θᵀθ I₃ = I₃ and ḠᵀḠ = GᵀG = I₄ − θθᵀ: 4-term sums, ≲ 4 ulp, plus θᵀθ − 1 ≲ 2ε
    // → 8ε.
    check_close(g_bar * g_bar.transpose(), Eigen::Matrix3d::Identity(), 8.0 * kEps);
    check_close(g * g.transpose(), Eigen::Matrix3d::Identity(), 8.0 * kEps);
    const Eigen::Matrix4d projector = Eigen::Matrix4d::Identity() - theta * theta.transpose();
    check_close(g_bar.transpose() * g_bar, projector, 8.0 * kEps);
    check_close(g.transpose() * g, projector, 8.0 * kEps);
    // A = GḠᵀ, and so G = AḠ (ω = Aω̄): 4-term sums of O(1) products, against A's own ≲ 3 ulp
    // (and, for the second, one more product with A): 16ε.
    const Eigen::Matrix3d a = rotation::rotation_matrix(theta);
    check_close(g * g_bar.transpose(), a, 16.0 * kEps);
    check_close(a * g_bar, g, 16.0 * kEps);
  }
}

TEST_CASE("body angular velocity is 2 G-bar theta-dot (constant body rate)", "[euler]") {
  // θ(t) = θ0 ⊗ exp(t w) is the exact attitude under the constant body-frame angular velocity
  // w, since A(θ(t)) = A(θ0) exp(t w̃) and A⁻¹Ȧ = w̃.
  const std::vector<Eigen::Vector3d> rates = {Eigen::Vector3d(0.3, -1.1, 0.7),
                                              Eigen::Vector3d(-2.0, 0.5, 0.1)};
  for (const AttitudeSample& sample : attitude_samples()) {
    for (const Eigen::Vector3d& w_B : rates) {
      INFO(sample.name << ", theta0 = " << sample.theta.transpose()
                       << ", w_B = " << w_B.transpose());
      const rotation::EulerParameters theta0 = sample.theta;
      const auto theta_of_t = [&](double t) -> Eigen::VectorXd {
        return rotation::quaternion_multiply(theta0, rotation::exp_quaternion(t * w_B));
      };
      for (const double t : {0.0, 0.7}) {
        INFO("t = " << t);
        const rotation::EulerParameters theta = theta_of_t(t);
        const rotation::EulerParameters theta_dot = time_derivative(theta_of_t, t);
        const Eigen::Matrix3d a = rotation::rotation_matrix(theta);
        // ω̄ = 2Ḡθ̇ (body) and ω = 2Gθ̇ = Aω̄ (global). |θ'''| = |w|³/8 ≤ 1.2: see the
        // tolerance's derivation; relative to max(1, |w|).
        check_close(2.0 * rotation::g_bar_matrix(theta) * theta_dot, w_B,
                    kFiniteDifferenceTolerance);
        check_close(2.0 * rotation::g_matrix(theta) * theta_dot, a * w_B,
                    kFiniteDifferenceTolerance);
        // θ̇ = euler_parameter_rate(θ, ω̄) against the finite difference.
        const rotation::EulerParameters rate = rotation::euler_parameter_rate(theta, w_B);
        check_close(rate, theta_dot, kFiniteDifferenceTolerance);
        // … and against its two closed forms, ½Ḡᵀω̄ and ½θ⊗(0, ω̄): the same products summed
        // in another order, ≲ 2 ulp of |θ||w| → 4ε.
        check_close(rate, 0.5 * rotation::g_bar_matrix(theta).transpose() * w_B, 4.0 * kEps);
        check_close(rate, 0.5 * rotation::quaternion_multiply(theta, pure_quaternion(w_B)),
                    4.0 * kEps);
        // Ȧ = A ω̄̃ = ω̃ A by central differences of A(θ(t)).
        const Eigen::Matrix3d a_dot = unflatten(time_derivative(
            [&](double tau) { return flatten(rotation::rotation_matrix(theta_of_t(tau))); }, t));
        check_close(a_dot, a * rotation::hat(w_B), kFiniteDifferenceTolerance);
        check_close(a_dot, rotation::hat(a * w_B) * a, kFiniteDifferenceTolerance);
      }
    }
  }
}

TEST_CASE("G-bar(theta-dot) theta-dot = 0, so body angular acceleration is 2 G-bar theta-ddot",
          "[euler]") {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 20; ++i) {
    // Any 4-vector v (not only unit ones): Ḡ(v)v = G(v)v = 0, products cancelling in pairs:
    // ≲ 2 ulp of |v|² → 4ε|v|².
    const Eigen::Vector4d v(normal(rng), normal(rng), normal(rng), normal(rng));
    INFO("v = " << v.transpose());
    check_close(rotation::g_bar_matrix(v) * v, Eigen::Vector3d::Zero(),
                4.0 * kEps * v.squaredNorm());
    check_close(rotation::g_matrix(v) * v, Eigen::Vector3d::Zero(), 4.0 * kEps * v.squaredNorm());
  }
  // A non-constant, non-commuting body rate: θ(t) = θ0 ⊗ exp(φ(t)) with φ(t) = t w + ½t² α0.
  // Then A(θ)ᵀȦ = exp(φ̃)ᵀ d/dt exp(φ̃) = (J_r(φ) φ̇)~, so ω̄(t) = J_r(φ(t)) φ̇(t), and at t = 0
  // (J_r(0) = I, d/dt J_r = −½ŵ, ŵw = 0) the body angular acceleration is exactly α0.
  const Eigen::Vector3d w(0.3, -1.1, 0.7);
  const Eigen::Vector3d alpha0(-0.9, 0.4, 1.3);
  const auto phi = [&](double t) -> Eigen::Vector3d { return t * w + 0.5 * t * t * alpha0; };
  const auto phi_dot = [&](double t) -> Eigen::Vector3d { return w + t * alpha0; };
  std::vector<AttitudeSample> samples = attitude_samples();
  for (const AttitudeSample& sample : samples) {
    const rotation::EulerParameters theta0 = sample.theta;
    const auto theta_of_t = [&](double t) -> Eigen::VectorXd {
      return rotation::quaternion_multiply(theta0, rotation::exp_quaternion(phi(t)));
    };
    const auto w_B_of_t = [&](double t) -> Eigen::VectorXd {
      return rotation::right_jacobian(phi(t)) * phi_dot(t);
    };
    // θ̇(t) from the kinematic equation, analytic in t.
    const auto theta_dot_of_t = [&](double t) -> Eigen::VectorXd {
      return rotation::euler_parameter_rate(theta_of_t(t), w_B_of_t(t));
    };
    for (const double t : {0.0, 0.4}) {
      INFO(sample.name << ", theta0 = " << sample.theta.transpose() << ", t = " << t);
      const rotation::EulerParameters theta = theta_of_t(t);
      const Eigen::Vector3d w_B = w_B_of_t(t);
      // The kinematic equation with ω̄ from so3's right Jacobian matches θ̇ by differences:
      // ties J_r's convention to Ḡ's.
      const rotation::EulerParameters theta_dot = time_derivative(theta_of_t, t);
      check_close(theta_dot_of_t(t), theta_dot, kFiniteDifferenceTolerance);
      check_close(2.0 * rotation::g_bar_matrix(theta) * theta_dot, w_B, kFiniteDifferenceTolerance);
      // Premise of α̅ = 2Ḡθ̈: d/dt(2Ḡθ̇) = 2Ḡ(θ̇)θ̇ + 2Ḡθ̈ (Ḡ is linear in θ), the first term 0.
      const rotation::EulerParameters theta_dot_exact = theta_dot_of_t(t);
      check_close(rotation::g_bar_matrix(theta_dot_exact) * theta_dot_exact,
                  Eigen::Vector3d::Zero(), 4.0 * kEps);
      // α̅ = ω̄̇ = 2Ḡθ̈, with θ̈ and ω̄̇ each by one central difference of an analytic rate
      // (third derivatives O(|w| + |α0|)³ ≲ 10 → ≲ 1e-10).
      const rotation::EulerParameters theta_ddot = time_derivative(theta_dot_of_t, t);
      const Eigen::Vector3d alpha_B = time_derivative(w_B_of_t, t);
      check_close(2.0 * rotation::g_bar_matrix(theta) * theta_ddot, alpha_B,
                  kFiniteDifferenceTolerance);
      if (t == 0.0) {
        check_close(2.0 * rotation::g_bar_matrix(theta) * theta_ddot, alpha0,
                    kFiniteDifferenceTolerance);
      }
      // Ȧ = A ω̄̃ along this path too.
      const Eigen::Matrix3d a_dot = unflatten(time_derivative(
          [&](double tau) { return flatten(rotation::rotation_matrix(theta_of_t(tau))); }, t));
      check_close(a_dot, rotation::rotation_matrix(theta) * rotation::hat(w_B),
                  kFiniteDifferenceTolerance);
    }
  }
}

TEST_CASE("quaternion_multiply composes rotations", "[euler]") {
  // Hamilton's rules i ⊗ j = k = −(j ⊗ i): exact.
  const rotation::EulerParameters i(0.0, 1.0, 0.0, 0.0);
  const rotation::EulerParameters j(0.0, 0.0, 1.0, 0.0);
  const rotation::EulerParameters k(0.0, 0.0, 0.0, 1.0);
  CHECK(rotation::quaternion_multiply(i, j) == k);
  CHECK(rotation::quaternion_multiply(j, i) == -k);
  CHECK(rotation::quaternion_multiply(i, i) == -rotation::identity_euler_parameters());
  std::mt19937 rng(6);
  for (int n = 0; n < 20; ++n) {
    const rotation::EulerParameters p = random_unit_quaternion(rng);
    const rotation::EulerParameters q = random_unit_quaternion(rng);
    const rotation::EulerParameters r = random_unit_quaternion(rng);
    INFO("p = " << p.transpose() << ", q = " << q.transpose() << ", r = " << r.transpose());
    const rotation::EulerParameters pq = rotation::quaternion_multiply(p, q);
    // A(p ⊗ q) = A(p) A(q): each side a few ulp of O(1) entries, the product adds a 3-term
    // sum: 16ε.
    check_close(rotation::rotation_matrix(pq),
                rotation::rotation_matrix(p) * rotation::rotation_matrix(q), 16.0 * kEps);
    // Norm is multiplicative: ≲ 4 roundings per component → 4ε.
    check_close(pq.norm(), 1.0, 4.0 * kEps);
    // Associativity: two 4-term products each way, O(1) values: 8ε.
    check_close(rotation::quaternion_multiply(pq, r),
                rotation::quaternion_multiply(p, rotation::quaternion_multiply(q, r)), 8.0 * kEps);
    // The identity is neutral (multiplications by 1 and additions of 0: exact).
    CHECK(rotation::quaternion_multiply(rotation::identity_euler_parameters(), p) == p);
    CHECK(rotation::quaternion_multiply(p, rotation::identity_euler_parameters()) == p);
    // p ⊗ p* = 1 (up to |p|² − 1 and a 4-term sum: 4ε); A(p*) = A(p)ᵀ (negation of the odd
    // e0 ẽ term only: ≲ 1 ulp → 4ε).
    check_close(rotation::quaternion_multiply(p, rotation::quaternion_conjugate(p)),
                rotation::identity_euler_parameters(), 4.0 * kEps);
    check_close(rotation::rotation_matrix(rotation::quaternion_conjugate(p)),
                rotation::rotation_matrix(p).transpose(), 4.0 * kEps);
  }
  // exp_quaternion(φ) ⊗ exp_quaternion(ψ) ↦ exp(φ̃) exp(ψ̃) (body → global composition).
  for (int n = 0; n < 20; ++n) {
    std::normal_distribution<double> normal;
    const Eigen::Vector3d phi(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3d psi(normal(rng), normal(rng), normal(rng));
    INFO("phi = " << phi.transpose() << ", psi = " << psi.transpose());
    check_close(rotation::rotation_matrix(rotation::quaternion_multiply(
                    rotation::exp_quaternion(phi), rotation::exp_quaternion(psi))),
                rotation::exp_so3(phi) * rotation::exp_so3(psi), 16.0 * kEps);
  }
}

TEST_CASE("exp_quaternion agrees with exp_so3 and its own reference", "[euler]") {
  for (const RotationSample& s : quaternion_branch_samples()) {
    INFO(s.name << ", phi = " << s.phi.transpose());
    const rotation::EulerParameters theta = rotation::exp_quaternion(s.phi);
    // Unit: cos² + sin² of correctly-rounded values, ≲ 2 ulp → 4ε.
    check_close(theta.norm(), 1.0, 4.0 * kEps);
    // A(exp_quaternion(φ)) = exp_so3(φ): both ≲ 3 ulp per O(1) entry → 16ε.
    check_close(rotation::rotation_matrix(theta), rotation::exp_so3(s.phi), 16.0 * kEps);
    // Long-double reference (cos(x/2), sin(x/2)/x · φ): no cancellation in either, so it is
    // good to ε_ld; the double result, Taylor branch included, to ≲ 2 ulp → 4ε.
    const Eigen::Matrix<long double, 3, 1> p = s.phi.cast<long double>();
    const long double x = p.norm();
    Eigen::Matrix<long double, 4, 1> reference;
    reference(0) = std::cos(0.5L * x);
    reference.tail<3>() = (x > 0.0L ? std::sin(0.5L * x) / x : 0.5L) * p;
    check_close(theta, reference.cast<double>(), 4.0 * kEps);
  }
  // Continuity across the branch switch at |φ|/2 = 1e-2: along e_x, |φ| is exact, so the two
  // samples are one ulp apart on either side; the functions move by ~1e-18 over that step, so
  // only the ≲ 2 ulp of each branch remain: 4ε.
  const Eigen::Vector3d below =
      std::nextafter(kQuaternionBranchAngle, 0.0) * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d above = kQuaternionBranchAngle * Eigen::Vector3d::UnitX();
  check_close(rotation::exp_quaternion(below), rotation::exp_quaternion(above), 4.0 * kEps);
}

TEST_CASE("log_quaternion inverts exp_quaternion and agrees with log_so3", "[euler]") {
  CHECK(rotation::log_quaternion(rotation::identity_euler_parameters()) == Eigen::Vector3d::Zero());
  for (const RotationSample& s : quaternion_branch_samples()) {
    INFO(s.name << ", phi = " << s.phi.transpose());
    const double angle = s.phi.norm();
    const rotation::EulerParameters theta = rotation::exp_quaternion(s.phi);
    const Eigen::Vector3d log_theta = rotation::log_quaternion(theta);
    const Eigen::Vector3d log_minus_theta = rotation::log_quaternion(-theta);
    const Eigen::Vector3d log_a = rotation::log_so3(rotation::rotation_matrix(theta));
    INFO("log_quaternion = " << log_theta.transpose() << ", log_so3 = " << log_a.transpose());
    // |φ| ≤ π up to the rounding of 2·atan2 and of the axis scaling: π(1 + 4ε).
    CHECK(log_theta.norm() <= kPi * (1.0 + 4.0 * kEps));
    // 2·atan2(|e|, e0)·e/|e| keeps the relative accuracy of θ's components (≲ 2 ulp) and adds
    // ≲ 4 roundings: 16ε·|φ| absolute, a factor 2 to spare. log_so3 of A(θ) likewise.
    const double tolerance = 16.0 * kEps * std::max(angle, 1e-300);
    if (theta(0) > 4.0 * kEps) {
      // Sign of e0 determined beyond round-off (at π − 1e-10, e0 = 5e-11): unique answer.
      CHECK((log_theta - s.phi).norm() <= tolerance);
      CHECK((log_minus_theta - s.phi).norm() <= tolerance);  // shortest rotation of ±θ
      CHECK((log_a - s.phi).norm() <= tolerance);
    } else {
      // At |φ| = π, ±φ are the same rotation: either answer is correct.
      CHECK(std::min((log_theta - s.phi).norm(), (log_theta + s.phi).norm()) <= tolerance);
      CHECK(std::min((log_minus_theta - s.phi).norm(), (log_minus_theta + s.phi).norm()) <=
            tolerance);
      CHECK(std::min((log_a - s.phi).norm(), (log_a + s.phi).norm()) <= tolerance);
    }
  }
  // A quaternion in the e0 < 0 hemisphere, (cos(α/2), sin(α/2) n) with α = 3π/2, is the
  // rotation by −π/2 about n: the logarithm returns the shortest vector. ≲ 16ε·π/2.
  const double alpha = 1.5 * kPi;
  const Eigen::Vector3d n = generic_axis();
  rotation::EulerParameters theta;
  theta << std::cos(0.5 * alpha), std::sin(0.5 * alpha) * n;
  check_close(rotation::log_quaternion(theta), -0.5 * kPi * n, 16.0 * kEps);
  // Tiny angles keep full relative accuracy (down to the e → 2e branch below 1e-300):
  // componentwise ≲ 4ε relative; 16ε leaves a factor 4.
  for (const double tiny : {1e-300, 1e-100, 1e-8}) {
    const Eigen::Vector3d phi = tiny * generic_axis();
    const Eigen::Vector3d log_theta = rotation::log_quaternion(rotation::exp_quaternion(phi));
    INFO("phi = " << phi.transpose() << ", log = " << log_theta.transpose());
    CHECK((log_theta - phi).cwiseAbs().maxCoeff() <= 16.0 * kEps * phi.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("euler_parameters_from_matrix round-trips with e0 >= 0", "[euler]") {
  std::vector<AttitudeSample> samples = attitude_samples();
  std::mt19937 rng(7);
  for (int n = 0; n < 20; ++n) samples.push_back({"random", random_unit_quaternion(rng)});
  for (const AttitudeSample& sample : samples) {
    INFO(sample.name << ", theta = " << std::setprecision(17) << sample.theta.transpose());
    const rotation::EulerParameters& theta = sample.theta;
    const Eigen::Matrix3d a = rotation::rotation_matrix(theta);
    const rotation::EulerParameters q = rotation::euler_parameters_from_matrix(a);
    INFO("euler_parameters_from_matrix(A(theta)) = " << q.transpose());
    CHECK(q(0) >= 0.0);
    check_close(q.norm(), 1.0, 4.0 * kEps);
    // Shepperd: the largest component from a square root of a sum of O(1) diagonal entries,
    // the others from sums/differences of off-diagonal ones divided by it: each ≲ 4 ulp of A's
    // own ≲ 3-ulp entries → |q − ±θ| ≲ 8ε per component.
    if (std::abs(theta(0)) > 8.0 * kEps) {
      // e0 resolved beyond round-off: the answer is the e0 ≥ 0 one of ±θ.
      check_close(q, theta(0) > 0.0 ? theta : rotation::EulerParameters(-theta), 8.0 * kEps);
    } else {
      // |φ| = π: e0 = 0 up to round-off, both signs are e0 ≥ 0 representatives.
      CHECK(std::min((q - theta).cwiseAbs().maxCoeff(), (q + theta).cwiseAbs().maxCoeff()) <=
            8.0 * kEps);
    }
    // A(q) = A: 16ε (A's own ≲ 3 ulp, q's ≲ 8ε entering linearly).
    check_close(rotation::rotation_matrix(q), a, 16.0 * kEps);
  }
  // Matrices from an independent source (exp_so3, so not exactly A(θ) of any θ), at and near
  // π in several directions, where the rounded |φ| can exceed π: e0 must still be ≥ 0.
  for (const RotationSample& s : quaternion_branch_samples()) {
    INFO(s.name << ", phi = " << s.phi.transpose());
    const Eigen::Matrix3d r = rotation::exp_so3(s.phi);
    const rotation::EulerParameters q = rotation::euler_parameters_from_matrix(r);
    INFO("q = " << std::setprecision(17) << q.transpose());
    CHECK(q(0) >= 0.0);
    check_close(rotation::rotation_matrix(q), r, 16.0 * kEps);
  }
}

TEST_CASE("geodesic_angle is the bi-invariant distance |log(A(a)^T A(b))|", "[euler]") {
  std::mt19937 rng(8);
  std::normal_distribution<double> normal;
  const auto random_direction = [&]() {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  };
  for (int n = 0; n < 20; ++n) {
    const rotation::EulerParameters a = random_unit_quaternion(rng);
    const rotation::EulerParameters b = random_unit_quaternion(rng);
    INFO("a = " << a.transpose() << ", b = " << b.transpose());
    const double angle = rotation::geodesic_angle(a, b);
    CHECK(angle >= 0.0);
    CHECK(angle <= kPi);
    // The components of a*⊗b carry ≲ 4 ulp of O(1) terms; 2·atan2 on the unit circle maps
    // that to ≲ 8ε absolute in the angle. Swapping a and b negates the vector part only
    // (rounding is sign-symmetric), negating b changes the sign of everything: 8ε.
    check_close(rotation::geodesic_angle(b, a), angle, 8.0 * kEps);
    check_close(rotation::geodesic_angle(a, -b), angle, 8.0 * kEps);
    // Zero distance to itself (pairwise cancelling products): ≤ 4ε.
    CHECK(rotation::geodesic_angle(a, a) <= 4.0 * kEps);
    // Against the matrix logarithm: A(a)ᵀA(b) has ≲ 8 ulp per entry, and log_so3 (Shepperd +
    // atan2) keeps that absolute: 16ε·π.
    const Eigen::Matrix3d relative =
        rotation::rotation_matrix(a).transpose() * rotation::rotation_matrix(b);
    check_close(angle, rotation::log_so3(relative).norm(), 16.0 * kEps * kPi);
  }
  for (int n = 0; n < 20; ++n) {
    const rotation::EulerParameters a = random_unit_quaternion(rng);
    const Eigen::Vector3d direction = random_direction();
    // Small angles, relative 1e-6: rounding the 4 components of b = a ⊗ exp(δ) (½ ulp each)
    // alone moves the attitude by up to ~4.4e-16 rad, and forming a*⊗b adds ≲ 4 roundings of
    // O(1) terms per component (~4e-16 more in |vec|, which is ½ the angle): ≲ 1e-15
    // absolute, i.e. 1e-6 of 1e-9.
    const Eigen::Vector3d delta = 1e-9 * direction;
    INFO("a = " << a.transpose() << ", delta = " << delta.transpose());
    const rotation::EulerParameters b_body =
        rotation::quaternion_multiply(a, rotation::exp_quaternion(delta));
    const rotation::EulerParameters b_global =
        rotation::quaternion_multiply(rotation::exp_quaternion(delta), a);
    check_close(rotation::geodesic_angle(a, b_body) / 1e-9, 1.0, 1e-6);
    check_close(rotation::geodesic_angle(a, b_global) / 1e-9, 1.0, 1e-6);
    // Generic, near π, and past π (where the shorter way round is 2π − |δ|). The composition
    // and the angle each carry ≲ 8ε absolute: 16ε·π.
    for (const double magnitude : {0.3, 2.0, kPi - 1e-6, kPi - 1e-10, kPi, kPi + 0.5}) {
      INFO("|delta| = " << magnitude);
      const double expected = magnitude <= kPi ? magnitude : 2.0 * kPi - magnitude;
      const Eigen::Vector3d big_delta = magnitude * direction;
      check_close(rotation::geodesic_angle(
                      a, rotation::quaternion_multiply(a, rotation::exp_quaternion(big_delta))),
                  expected, 16.0 * kEps * kPi);
      check_close(rotation::geodesic_angle(
                      rotation::quaternion_multiply(rotation::exp_quaternion(big_delta), a), a),
                  expected, 16.0 * kEps * kPi);
    }
  }
}

}  // namespace
}  // namespace flexref::core
