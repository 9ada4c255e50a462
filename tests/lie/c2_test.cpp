#include "lie/c2.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "tests/support/test_problems.hpp"

namespace flexref::lie {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

TEST_CASE("C2 conserves the angular momentum of free_spin to round-off, not the energy",
          "[lie][c2]") {
  const core::Model model = testing::free_spin();
  C2Stepper stepper(model);
  stepper.initialize(0.0, model.initial_state());
  const double energy0 = model.kinetic_energy(stepper.state());
  const Vector3d momentum0 = model.angular_momentum_W(stepper.state());
  double energy_drift = 0.0;
  double momentum_drift = 0.0;
  for (int n = 0; n < 10000; ++n) {
    REQUIRE(stepper.step(0.01).ok);
    energy_drift =
        std::max(energy_drift, std::abs(model.kinetic_energy(stepper.state()) - energy0) / energy0);
    momentum_drift =
        std::max(momentum_drift,
                 (model.angular_momentum_W(stepper.state()) - momentum0).norm() / momentum0.norm());
  }
  // π_{n+1} = R_{n+1} J J⁻¹ R_{n+1}ᵀ π_n: exact up to the rounding of the rotation, its
  // transpose, J and J⁻¹ (≈ 4ε per step), which can add up linearly: 1e4·4ε ≈ 9e-12.
  // Measured 4.3e-12 (a bias of ≈ 2ε per step).
  CHECK(momentum_drift <= 1e-11);
  // The energy error is the scheme's, O(h²), and grows secularly (measured max |ΔE|/E:
  // 7.9e-7 over 1e4 steps, 5.2e-6 over 1e5, 5.0e-5 over 1e6). Lower bound: the check can
  // fail (C2 does not conserve energy; a change that made it conserve it would be a different
  // scheme). Upper bound: 2.5× the measured value, so that a doubled error constant or a lost
  // order (O(h) would be ~1e2× larger) is caught.
  CHECK(energy_drift >= 1e-7);
  CHECK(energy_drift <= 2e-6);
}

TEST_CASE("C2 balances the angular momentum with the trapezoidal torque impulse", "[lie][c2]") {
  // book_toss during its pulse: π_{n+1} − π_n = (h/2)(Γ_n + Γ_{n+1}) with the world torque
  // Γ(t) = (0.2, 0, 0.2) sin²(πt/0.1) known in closed form. A sign error in the balance or a
  // torque evaluated at the wrong time shows at O(h|Γ|) ≈ 1e-4.
  const core::Model model = testing::book_toss();
  C2Stepper stepper(model);
  stepper.initialize(0.0, model.initial_state());
  const double h = 1e-3;
  auto torque = [](double t) {
    const double s = std::sin(std::numbers::pi * t / 0.1);
    return Vector3d(Vector3d(0.2, 0.0, 0.2) * s * s);
  };
  for (int n = 0; n < 60; ++n) {
    const double t_n = stepper.time();
    const Vector3d pi_n = model.angular_momentum_W(stepper.state());
    REQUIRE(stepper.step(h).ok);
    const Vector3d pi_np1 = model.angular_momentum_W(stepper.state());
    // Round-off of π (|π| = 20) through a few rotations: ≈ 1e-14; the torque values carry
    // relative round-off ε.
    CHECK((pi_np1 - pi_n - 0.5 * h * (torque(t_n) + torque(t_n + h))).norm() <= 1e-13);
  }
}

TEST_CASE("C2 starts from the Euler acceleration and keeps A_{n+1} = (W_{n+1} − W_n)/h",
          "[lie][c2]") {
  const core::Model model = testing::free_spin();
  C2Stepper stepper(model);
  stepper.initialize(0.0, model.initial_state());
  const Matrix3d& J = model.body(0).I_Br_B();
  const Vector3d w0 = model.initial_state()[0].w_WB_B;
  const Vector3d euler = J.inverse() * (-w0.cross(J * w0));
  // The stepper's own formulas, evaluated here once more: the same few roundings of O(|α̅|)
  // terms (J is diagonal), ≤ 4 ε = 8.9e-16 of |α̅|.
  CHECK((stepper.accelerations()[0].alpha_WB_B - euler).norm() <= 1e-15 * euler.norm());
  REQUIRE(stepper.step(0.01).ok);
  const Vector3d newmark = (stepper.state()[0].w_WB_B - w0) / 0.01;
  CHECK((stepper.accelerations()[0].alpha_WB_B - newmark).norm() <= 1e-15 * newmark.norm());
}

}  // namespace
}  // namespace flexref::lie
