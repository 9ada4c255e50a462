/// Property tests for core/so3: hat/vee, exp/log, and the left and right Jacobians (dexp,
/// dexp⁻¹) on rotation vectors at 0, 1e-8, both sides of the small-angle branch switch,
/// generic, and near π (docs/design/style.md "Tests"; conventions of docs/design/model.md
/// "Kinematics").
#include "rotation/so3.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

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
// The branch switch in so3.cpp (kSmallAngle): Taylor series below, closed forms above.
constexpr double kBranchAngle = 1e-2;

using Sample = flexref::testing::RotationSample;
using flexref::testing::generic_axis;

/// Rotation vectors covering every branch of so3.cpp. Fixed seed.
std::vector<Sample> so3_branch_samples() {
  return flexref::testing::rotation_vector_samples({kBranchAngle}, 20240611u);
}

// Independent reference: the Rodrigues-type formulas evaluated in long double, with the scalar
// coefficients from their Taylor series for |φ| < kSeriesAngle (summed until the terms vanish
// in long double) and from the closed forms above. A closed-form coefficient c_k multiplies
// φ̃^k, and c_k·|φ|^k carries only the absolute cancellation error of a few ε_ld ≈ 1e-19, far
// below a double ulp of the O(1) matrix entries.
using Matrix3ld = Eigen::Matrix<long double, 3, 3>;
using Vector3ld = Eigen::Matrix<long double, 3, 1>;

Matrix3ld hat_ld(const Vector3ld& a) {
  Matrix3ld m;
  m << 0.0L, -a.z(), a.y(), a.z(), 0.0L, -a.x(), -a.y(), a.x(), 0.0L;
  return m;
}

constexpr long double kSeriesAngle = 0.05L;

// Σ_k (−x²)^k / (n + 2k)! with first_term = 1/n!: term_{k+1} = term_k·(−x²)/((n+2k+1)(n+2k+2)).
long double alternating_series(long double first_term, int first_factorial_index, long double x) {
  long double sum = 0.0L;
  long double term = first_term;
  int n = first_factorial_index;
  for (int k = 0; k < 20; ++k) {
    sum += term;
    term *= -x * x / static_cast<long double>((n + 1) * (n + 2));
    n += 2;
  }
  return sum;
}

long double sinc_ld(long double x) {  // sin x / x = Σ (−x²)^k/(2k+1)!
  return x < kSeriesAngle ? alternating_series(1.0L, 1, x) : std::sin(x) / x;
}
long double one_minus_cos_over_x2_ld(long double x) {  // Σ (−x²)^k/(2k+2)!
  return x < kSeriesAngle ? alternating_series(0.5L, 2, x) : (1.0L - std::cos(x)) / (x * x);
}
long double x_minus_sin_over_x3_ld(long double x) {  // Σ (−x²)^k/(2k+3)!
  return x < kSeriesAngle ? alternating_series(1.0L / 6.0L, 3, x) : (x - std::sin(x)) / (x * x * x);
}
long double dexp_inv_coefficient_ld(long double x) {
  // (1 − (x/2)cot(x/2))/x² = Σ_{n≥1} |B_2n| x^(2n−2)/(2n)! (Bernoulli numbers)
  //   = 1/12 + x²/720 + x⁴/30240 + x⁶/1209600 + x⁸/47900160 + 691x¹⁰/1307674368000 + …;
  // the next term relative to 1/12 is ≤ 1.6e-26 for x < 0.05.
  if (x < kSeriesAngle) {
    const long double x2 = x * x;
    return 1.0L / 12.0L +
           x2 * (1.0L / 720.0L +
                 x2 * (1.0L / 30240.0L +
                       x2 * (1.0L / 1209600.0L +
                             x2 * (1.0L / 47900160.0L + x2 * (691.0L / 1307674368000.0L)))));
  }
  const long double half = 0.5L * x;
  return (1.0L - half * std::cos(half) / std::sin(half)) / (x * x);
}

Eigen::Matrix3d exp_reference(const Eigen::Vector3d& phi) {
  const Vector3ld p = phi.cast<long double>();
  const long double x = p.norm();
  const Matrix3ld h = hat_ld(p);
  return (Matrix3ld::Identity() + sinc_ld(x) * h + one_minus_cos_over_x2_ld(x) * h * h)
      .cast<double>();
}
Eigen::Matrix3d dexp_reference(const Eigen::Vector3d& phi) {
  const Vector3ld p = phi.cast<long double>();
  const long double x = p.norm();
  const Matrix3ld h = hat_ld(p);
  return (Matrix3ld::Identity() + one_minus_cos_over_x2_ld(x) * h +
          x_minus_sin_over_x3_ld(x) * h * h)
      .cast<double>();
}
Eigen::Matrix3d dexp_inv_reference(const Eigen::Vector3d& phi) {
  const Vector3ld p = phi.cast<long double>();
  const long double x = p.norm();
  const Matrix3ld h = hat_ld(p);
  return (Matrix3ld::Identity() - 0.5L * h + dexp_inv_coefficient_ld(x) * h * h).cast<double>();
}

TEST_CASE("hat and vee are inverse and hat(a) b = a x b", "[so3]") {
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  // Sign convention pinned on the basis: ê_x e_y = e_z (right-handed cross product).
  CHECK(rotation::hat(Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitY() ==
        Eigen::Vector3d::UnitZ());
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d a(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3d b(normal(rng), normal(rng), normal(rng));
    // vee(hat(a)) = ½(a − (−a)): one exact doubling and halving, so bitwise a.
    CHECK(rotation::vee(rotation::hat(a)) == a);
    // hat(a) is skew: its entries are ±a_i exactly.
    CHECK(rotation::hat(a).transpose() == -rotation::hat(a));
    // hat(a) b and a × b form the same two products per entry, possibly summed with one more
    // rounding (the exact zero on the diagonal): ≤ 2 ulp of |a||b| → 4ε|a||b|.
    check_close(rotation::hat(a) * b, a.cross(b), 4.0 * kEps * a.norm() * b.norm());
    // vee of a general matrix is its skew part: vee(M) = vee(½(M − Mᵀ)), same roundings.
    const Eigen::Matrix3d m = rotation::hat(a) + b * a.transpose();
    check_close(rotation::vee(m), rotation::vee(0.5 * (m - m.transpose())),
                4.0 * kEps * (1.0 + a.norm() * b.norm()));
  }
}

TEST_CASE("exp_so3 is a rotation and agrees with Eigen::AngleAxisd and the reference", "[so3]") {
  // Sign convention pinned: a quarter turn about z maps e_x to e_y.
  check_close(rotation::exp_so3(0.5 * kPi * Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX(),
              Eigen::Vector3d::UnitY(), 4.0 * kEps);
  for (const Sample& s : so3_branch_samples()) {
    INFO(s.name << ", phi = " << s.phi.transpose());
    const Eigen::Matrix3d r = rotation::exp_so3(s.phi);
    // Each entry of R is I + a φ̃ + b φ̃² with O(1) terms and ≤ 5 roundings, so ≲ 3 ulp;
    // RᵀR sums three such products: ≲ 10ε. Use 16ε ≈ 3.6e-15.
    check_close(r.transpose() * r, Eigen::Matrix3d::Identity(), 16.0 * kEps);
    CHECK(std::abs(r.determinant() - 1.0) <= 16.0 * kEps);
    // Against the long-double reference: only the ≲ 3 ulp of the double evaluation remain.
    check_close(r, exp_reference(s.phi), 8.0 * kEps);
    if (s.phi.norm() > 0.0) {
      const Eigen::Matrix3d eigen_r =
          Eigen::AngleAxisd(s.phi.norm(), s.phi.normalized()).toRotationMatrix();
      // Both few-ulp accurate: 8ε each → 16ε.
      check_close(r, eigen_r, 16.0 * kEps);
    } else {
      CHECK(r == Eigen::Matrix3d::Identity());
    }
  }
}

TEST_CASE("log_so3 inverts exp_so3", "[so3]") {
  CHECK(rotation::log_so3(Eigen::Matrix3d::Identity()) == Eigen::Vector3d::Zero());
  for (const Sample& s : so3_branch_samples()) {
    INFO(s.name << ", phi = " << s.phi.transpose());
    const Eigen::Matrix3d r = rotation::exp_so3(s.phi);
    const Eigen::Vector3d log_r = rotation::log_so3(r);
    INFO("log_so3(exp_so3(phi)) = " << log_r.transpose());
    const double angle = s.phi.norm();
    // |log R| ≤ π up to the rounding of 2·atan2(…) and of the axis scaling: π(1 + 4ε).
    CHECK(log_r.norm() <= kPi * (1.0 + 4.0 * kEps));
    if (angle < kPi) {
      // Shepperd's quaternion carries absolute error ~ε in each component (relative ε near 0,
      // where all of R's off-diagonal entries are O(|φ|)), and 2 atan2 keeps it: the error is
      // ≲ 8ε·|φ|; 16ε|φ| leaves a factor 2. At π − 1e-10, e0 = 5e-11 ≫ ε keeps the sign.
      CHECK((log_r - s.phi).norm() <= 16.0 * kEps * angle);
    } else {
      // At exactly π, ±φ give the same rotation; either is correct.
      CHECK(std::min((log_r - s.phi).norm(), (log_r + s.phi).norm()) <= 16.0 * kEps * angle);
    }
    // exp ∘ log = id on SO(3): log's ≲ 8ε|φ| error, through the 1-Lipschitz exp, plus exp's
    // own few ulp: 16ε·max(1, |φ|).
    check_close(rotation::exp_so3(log_r), r, 16.0 * kEps * std::max(1.0, angle));
  }
}

TEST_CASE("log_so3 keeps full relative accuracy at tiny angles", "[so3]") {
  // Down to |φ| = 1e-300 (where squared norms underflow and log_so3 takes its e → 2e branch)
  // every entry of exp(φ̃) − I is O(|φ|) with relative error ε, and so is Shepperd's vector
  // part: componentwise relative error ≲ 4ε; 16ε leaves a factor 4.
  for (const double angle : {1e-300, 1e-200, 1e-100, 1e-20, 1e-8}) {
    const Eigen::Vector3d phi = angle * generic_axis();
    const Eigen::Vector3d log_r = rotation::log_so3(rotation::exp_so3(phi));
    INFO("phi = " << phi.transpose() << ", log_so3(exp_so3(phi)) = " << log_r.transpose());
    CHECK((log_r - phi).cwiseAbs().maxCoeff() <= 16.0 * kEps * phi.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("dexp is the left-trivialized differential of exp", "[so3]") {
  for (const Sample& s : so3_branch_samples()) {
    INFO(s.name << ", phi = " << s.phi.transpose());
    const Eigen::Matrix3d r = rotation::exp_so3(s.phi);
    // ∂vec(exp(φ))/∂φ, 9×3, by central differences. h = ε^(1/3)·max(1, |φ_j|) ≤ 2e-5: the
    // truncation error h²/6·|∂³exp| ≤ 7e-11 (|∂³exp| ≤ 1 per unit direction), round-off
    // ε/h ≈ 4e-11, so agreement to ~1e-10; 1e-8 leaves 100× margin and is still 1e8 times
    // smaller than any sign or convention error at |φ| ≥ 0.1.
    const Eigen::MatrixXd fd = central_difference_jacobian(
        [](const Eigen::VectorXd& x) { return flatten(rotation::exp_so3(Eigen::Vector3d(x))); },
        s.phi);
    const Eigen::Matrix3d j_left = rotation::dexp(s.phi);
    const Eigen::Matrix3d j_right = rotation::right_jacobian(s.phi);
    for (int k = 0; k < 3; ++k) {
      INFO("direction e_" << k);
      const Eigen::Vector3d delta = Eigen::Vector3d::Unit(k);
      const Eigen::Matrix3d d_exp = unflatten(fd.col(k));
      // d/dε exp(φ + εδ) = (dexp_φ δ)~ exp(φ)
      check_close(d_exp, rotation::hat(j_left * delta) * r, 1e-8);
      // exp(φ)ᵀ d/dε exp(φ + εδ) = (J_r(φ) δ)~; Rᵀ is orthogonal, entries grow ≤ 3×: same 1e-8.
      check_close(r.transpose() * d_exp, rotation::hat(j_right * delta), 1e-8);
    }
    // Structural identities: J_r(φ) = J_l(−φ) = J_l(φ)ᵀ and J_l = exp(φ) J_r (adjoint).
    // The first two are the same arithmetic on negated inputs: exact. The last is a product
    // of O(1) matrices each good to ≲ 3 ulp: 16ε·max(1, |φ|).
    CHECK(j_right == rotation::dexp(-s.phi));
    check_close(j_right, j_left.transpose(), 4.0 * kEps);
    check_close(j_left, r * j_right, 16.0 * kEps * std::max(1.0, s.phi.norm()));
    // φ̃φ = 0, so dexp_φ φ = φ: a few ulp of |φ|.
    check_close(j_left * s.phi, s.phi, 4.0 * kEps * std::max(1.0, s.phi.norm()));
    // Against the long-double reference, which also checks the Taylor coefficients of the
    // small-angle branch: entries are O(1 + |φ|²), each ≲ 3 ulp.
    check_close(j_left, dexp_reference(s.phi), 8.0 * kEps);
  }
}

TEST_CASE("dexp_inv and right_jacobian_inv invert dexp and right_jacobian", "[so3]") {
  // dexp⁻¹ blows up only at |φ| = 2π; on |φ| ≤ π its norm is ≤ 1 + π/2 + 1, so the whole
  // sample set, exact π included, is well conditioned.
  for (const Sample& s : so3_branch_samples()) {
    INFO(s.name << ", phi = " << s.phi.transpose());
    const double scale = std::max(1.0, s.phi.norm());
    const Eigen::Matrix3d j_left_inv = rotation::dexp_inv(s.phi);
    // Product of two O(1 + |φ|) matrices, each entry ≲ 3 ulp and a 3-term sum: ≲ 20ε·|φ|².
    // 32ε·max(1, |φ|)² ≈ 7e-14 at π.
    check_close(j_left_inv * rotation::dexp(s.phi), Eigen::Matrix3d::Identity(),
                32.0 * kEps * scale * scale);
    check_close(rotation::dexp(s.phi) * j_left_inv, Eigen::Matrix3d::Identity(),
                32.0 * kEps * scale * scale);
    check_close(rotation::right_jacobian_inv(s.phi) * rotation::right_jacobian(s.phi),
                Eigen::Matrix3d::Identity(), 32.0 * kEps * scale * scale);
    // J_r⁻¹(φ) = J_l⁻¹(φ)ᵀ: the same terms with φ̃ → −φ̃ = φ̃ᵀ, ≲ 1 ulp per entry difference.
    check_close(rotation::right_jacobian_inv(s.phi), j_left_inv.transpose(), 4.0 * kEps);
    // Against the long-double reference (checks the Taylor branch too): ≲ 3 ulp of O(1+|φ|²).
    check_close(j_left_inv, dexp_inv_reference(s.phi), 8.0 * kEps * scale);
  }
}

TEST_CASE("small-angle branches are continuous across the switch", "[so3]") {
  // Along e_x, |φ| is computed exactly (√(x²) = |x| in IEEE arithmetic), so these two samples
  // are one ulp apart and sit on different sides of the `x < kSmallAngle` test.
  const Eigen::Vector3d below = std::nextafter(kBranchAngle, 0.0) * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d above = kBranchAngle * Eigen::Vector3d::UnitX();
  // The functions change by |f'|·ulp(1e-2) ≈ 2e-18 over this step; what remains is the
  // accuracy of each branch, ≲ 3 ulp for each: 8ε ≈ 1.8e-15. A wrong x² Taylor coefficient
  // would show as ~1e-6, a wrong x⁴ one as ~1e-12.
  check_close(rotation::exp_so3(below), rotation::exp_so3(above), 8.0 * kEps);
  check_close(rotation::dexp(below), rotation::dexp(above), 8.0 * kEps);
  check_close(rotation::dexp_inv(below), rotation::dexp_inv(above), 8.0 * kEps);
  check_close(rotation::right_jacobian(below), rotation::right_jacobian(above), 8.0 * kEps);
  check_close(rotation::right_jacobian_inv(below), rotation::right_jacobian_inv(above), 8.0 * kEps);
  check_close(rotation::log_so3(rotation::exp_so3(below)), below, 16.0 * kEps * kBranchAngle);
  // Each side against the long-double reference (its series are summed far past ε).
  for (const Eigen::Vector3d& phi : {below, above}) {
    INFO("phi = " << phi.transpose());
    check_close(rotation::exp_so3(phi), exp_reference(phi), 4.0 * kEps);
    check_close(rotation::dexp(phi), dexp_reference(phi), 4.0 * kEps);
    check_close(rotation::dexp_inv(phi), dexp_inv_reference(phi), 4.0 * kEps);
  }
}

}  // namespace
}  // namespace flexref::core
