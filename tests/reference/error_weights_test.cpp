/// \file error_weights_test.cpp
/// reference/error_weights.hpp: the multistep references' tolerances per component.
#include "reference/error_weights.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace flexref::reference {
namespace {

/// One free body's layout [p(3) θ(4) v(3) ω̄(3)] and an integral, as in the ODE form.
std::vector<double> weights_free_body_state() {
  return {2.0, -1.0,  0.5,            // p
          0.6, 0.0,   0.8,      0.0,  // θ (unit)
          3.0, 0.0,   -4.0,           // v
          0.0, 150.0, -4.61538,       // ω̄
          7.5};                       // W_d
}

std::vector<double> tolerances_of(const ErrorWeights& weights, const std::vector<double>& y,
                                  double mean_step) {
  std::vector<double> ewt(y.size());
  weights.evaluate(y.data(), mean_step, ewt.data());
  for (double& w : ewt) w = 1.0 / w;
  return ewt;
}

}  // namespace

TEST_CASE("error weights: SUNDIALS' off the rotation, natural sizes on it", "[error_weights]") {
  const double rtol = 1e-10, atol = 1e-11, span = 2.0;
  const ErrorWeights weights(14, rtol, atol, span, {RotationBlock{3, 10}});
  const std::vector<double> y = weights_free_body_state();
  const double speed = std::sqrt(150.0 * 150.0 + 4.61538 * 4.61538);
  // Tolerances are sums and quotients of a few doubles: 1e-14 relative is ~50 ulp.
  const double eps = 1e-14;

  SECTION("before the first step (f = 1)") {
    const std::vector<double> tol = tolerances_of(weights, y, 0.0);
    for (std::size_t i : {0U, 1U, 2U, 7U, 8U, 9U, 13U}) {
      CAPTURE(i);
      CHECK(tol[i] == Approx(rtol * std::abs(y[i]) + atol).epsilon(eps));
    }
    // θ: the quaternion's size is 1 whatever its components; ω̄: the attitude's over T.
    for (std::size_t i = 3; i < 7; ++i) CHECK(tol[i] == Approx(rtol + atol).epsilon(eps));
    for (std::size_t i = 10; i < 13; ++i) {
      CHECK(tol[i] == Approx((rtol + atol) / span).epsilon(eps));
    }
  }

  SECTION("per unit step: f = (|ω̄| + 1/T) h̄") {
    const double mean_step = 1e-4;
    const double share = (speed + 1.0 / span) * mean_step;  // 0.015: one step turns 0.015 rad
    const std::vector<double> tol = tolerances_of(weights, y, mean_step);
    for (std::size_t i : {0U, 1U, 2U, 7U, 8U, 9U, 13U}) {
      CHECK(tol[i] == Approx(rtol * std::abs(y[i]) + atol).epsilon(eps));
    }
    for (std::size_t i = 3; i < 7; ++i) {
      CHECK(tol[i] == Approx(share * (rtol + atol)).epsilon(eps));
    }
    for (std::size_t i = 10; i < 13; ++i) {
      CHECK(tol[i] == Approx(share * (rtol + atol) / span).epsilon(eps));
    }
    // A step that turns the body more than a radian gets the whole tolerance, not more.
    const std::vector<double> coarse = tolerances_of(weights, y, 1.0);
    for (std::size_t i = 3; i < 7; ++i) CHECK(coarse[i] == Approx(rtol + atol).epsilon(eps));
  }

  SECTION("never below the rounding of the component") {
    const ErrorWeights tight(14, 1e-15, 1e-15, span, {RotationBlock{3, 10}});
    const std::vector<double> tol = tolerances_of(tight, y, 1e-6);
    const double ulp = std::numeric_limits<double>::epsilon();
    for (std::size_t i = 3; i < 7; ++i) {
      CHECK(tol[i] == Approx(ErrorWeights::kRoundoff * ulp).epsilon(eps));
    }
    for (std::size_t i = 10; i < 13; ++i) {
      CAPTURE(i);
      CHECK(tol[i] ==
            Approx(ErrorWeights::kRoundoff * ulp * (std::abs(y[i]) + 1.0 / span)).epsilon(eps));
    }
  }
}

TEST_CASE("error weights: algebraic components keep their own tolerance", "[error_weights]") {
  const double rtol = 1e-10, atol = 1e-11, span = 2.0;
  ErrorWeights weights(16, rtol, atol, span, {RotationBlock{3, 10}});
  weights.set_algebraic(14, 5e3);
  std::vector<double> y = weights_free_body_state();
  y.push_back(147.0);  // λ
  y.push_back(-0.5);   // μ
  const double mean_step = 1e-4;
  const std::vector<double> tol = tolerances_of(weights, y, mean_step);
  // As in the first test case: 1e-14 relative is ~50 ulp of a few operations.
  CHECK(tol[14] == Approx(rtol * 147.0 + 5e3).epsilon(1e-14));
  CHECK(tol[15] == Approx(rtol * 0.5 + 5e3).epsilon(1e-14));
  // IDA's masked RMS norm divides by all 16 components, 14 of them tested: the tested ones'
  // tolerances are divided by √(16/14), so that the test is their own RMS.
  const double dilution = std::sqrt(16.0 / 14.0);
  CHECK(tol[13] == Approx((rtol * 7.5 + atol) / dilution).epsilon(1e-14));
  CHECK(tol[0] == Approx((rtol * 2.0 + atol) / dilution).epsilon(1e-14));
  const double share = (std::sqrt(150.0 * 150.0 + 4.61538 * 4.61538) + 1.0 / span) * mean_step;
  for (std::size_t i = 3; i < 7; ++i) {
    CHECK(tol[i] == Approx(share * (rtol + atol) / dilution).epsilon(1e-14));
  }
}

TEST_CASE("error weights: IDA's index-2 floor", "[error_weights]") {
  // ErrorWeights::kIndex2Roundoff instead of kRoundoff below the share (error_weights.hpp): at
  // rtol = atol = 1e-15 and h̄ = 1e-6 the share's θ tolerance, 0.015 · 2e-15 = 3e-17, is below
  // both floors.
  const double span = 2.0;
  const ErrorWeights joints(14, 1e-15, 1e-15, span, {RotationBlock{3, 10}},
                            ErrorWeights::kIndex2Roundoff);
  const std::vector<double> y = weights_free_body_state();
  const std::vector<double> tol = tolerances_of(joints, y, 1e-6);
  const double ulp = std::numeric_limits<double>::epsilon();
  for (std::size_t i = 3; i < 7; ++i) {
    CHECK(tol[i] == Approx(ErrorWeights::kIndex2Roundoff * ulp).epsilon(1e-14));
  }
  for (std::size_t i = 10; i < 13; ++i) {
    CHECK(
        tol[i] ==
        Approx(ErrorWeights::kIndex2Roundoff * ulp * (std::abs(y[i]) + 1.0 / span)).epsilon(1e-14));
  }
  // Off the rotation, SUNDIALS' weights as with the default floor.
  CHECK(tol[0] == Approx(1e-15 * 2.0 + 1e-15).epsilon(1e-14));
}

TEST_CASE("error weights: on joints the floors grow with |p| / ℓ and |v| / ℓ", "[error_weights]") {
  // The body of weights_free_body_state at |p| = √5.25 = 2.291 m, |v| = 5 m/s, on joints of arm
  // ℓ = 0.1 m: a length row's rounding ε |p| is ε |p| / ℓ = 22.9 ε of attitude, a velocity
  // row's ε |v| / ℓ = 50 ε rad/s of angular velocity (error_weights.hpp). At rtol = atol =
  // 1e-15 and h̄ = 1e-6 every rotation tolerance is at its floor.
  const double span = 2.0, arm = 0.1;
  const ErrorWeights fixed(14, 1e-15, 1e-15, span, {RotationBlock{3, 10, 0, 7}},
                           ErrorWeights::kIndex2Roundoff);
  ErrorWeights joints = fixed;
  joints.set_joint_rounding(arm);
  const std::vector<double> y = weights_free_body_state();
  const std::vector<double> tol = tolerances_of(joints, y, 1e-6);
  const std::vector<double> tol_fixed = tolerances_of(fixed, y, 1e-6);
  const double floor = ErrorWeights::kIndex2Roundoff * std::numeric_limits<double>::epsilon();
  const double p = std::sqrt(2.0 * 2.0 + 1.0 + 0.25), v = 5.0;
  // Sums, square roots and quotients of a few doubles: 1e-14 relative is ~50 ulp.
  for (std::size_t i = 3; i < 7; ++i) {
    CHECK(tol[i] == Approx(floor * p / arm).epsilon(1e-14));
    CHECK(tol_fixed[i] == Approx(floor).epsilon(1e-14));
  }
  // ω̄ = (0, 150, −4.6): |v| / ℓ = 50 is above |ω̄_i| + 1/T for the first and third components,
  // below it for the second (150.5).
  CHECK(tol[10] == Approx(floor * v / arm).epsilon(1e-14));
  CHECK(tol[11] == Approx(floor * (150.0 + 1.0 / span)).epsilon(1e-14));
  CHECK(tol[12] == Approx(floor * v / arm).epsilon(1e-14));
  CHECK(tol_fixed[10] == Approx(floor / span).epsilon(1e-14));
  // Off the rotation the weights are SUNDIALS', whatever the joints.
  for (std::size_t i : {0u, 1u, 2u, 7u, 8u, 9u, 13u}) CHECK(tol[i] == tol_fixed[i]);

  // Near the origin (|p| < ℓ) the attitude's floor stays R ε: the rows' rounding is then the
  // arm's own.
  std::vector<double> near = y;
  near[0] = 0.01, near[1] = 0.0, near[2] = 0.0;
  const std::vector<double> tol_near = tolerances_of(joints, near, 1e-6);
  CHECK(tol_near[3] == Approx(floor).epsilon(1e-14));
}

TEST_CASE("error weights: dropping the share leaves SUNDIALS' weights", "[error_weights]") {
  // IDA's fallback (ida_solver.cpp): after drop_rotation_share the rotation's tolerances are
  // rtol |y_i| + atol, as on every other component.
  ErrorWeights weights(14, 1e-10, 1e-11, 2.0, {RotationBlock{3, 10}});
  CHECK(weights.weighs_rotation());
  weights.drop_rotation_share();
  CHECK(!weights.weighs_rotation());
  const std::vector<double> y = weights_free_body_state();
  const std::vector<double> tol = tolerances_of(weights, y, 1e-4);
  for (std::size_t i = 0; i < y.size(); ++i) {
    CAPTURE(i);
    // 1/w back to a tolerance: two roundings of ε/2 ≈ 1.1e-16 each; 1e-14 leaves 45×.
    CHECK(tol[i] == Approx(1e-10 * std::abs(y[i]) + 1e-11).epsilon(1e-14));
  }
}

TEST_CASE("error weights: no rotation blocks, SUNDIALS' weights", "[error_weights]") {
  const ErrorWeights weights(14, 1e-10, 1e-11, 2.0, {});
  const std::vector<double> y = weights_free_body_state();
  const std::vector<double> tol = tolerances_of(weights, y, 1e-4);
  for (std::size_t i = 0; i < y.size(); ++i) {
    CAPTURE(i);
    // 1/w back to a tolerance: two roundings of ε/2 ≈ 1.1e-16 each; 1e-14 leaves 45×.
    CHECK(tol[i] == Approx(1e-10 * std::abs(y[i]) + 1e-11).epsilon(1e-14));
  }
}

TEST_CASE("error weights: a run of one output time keeps SUNDIALS' weights", "[error_weights]") {
  const ErrorWeights weights(14, 1e-10, 1e-10, 0.0, {RotationBlock{3, 10}});
  const std::vector<double> y = weights_free_body_state();
  const std::vector<double> tol = tolerances_of(weights, y, 1e-3);
  for (std::size_t i = 0; i < y.size(); ++i) {
    CAPTURE(i);
    // 1/w back to a tolerance: two roundings of ε/2 ≈ 1.1e-16 each; 1e-14 leaves 45×.
    CHECK(tol[i] == Approx(1e-10 * std::abs(y[i]) + 1e-10).epsilon(1e-14));
  }
}

}  // namespace flexref::reference
