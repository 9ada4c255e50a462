#include "core/model.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "reference/ode_form.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/finite_difference.hpp"
#include "tests/support/test_models.hpp"

namespace flexref::core {
namespace {

// Total energy along the ODE flow: E(y + ε f) − E(y − ε f) over 2ε is dE/dt. For a
// conservative model it must vanish; a sign error in any force, arm or in the Euler equation
// makes it O(power) instead. The central difference with ε = 1e-5 has truncation error
// O(ε²·|E'''|) ≈ 1e-10·|E'''| and round-off ε_mach·|E|/ε ≈ 1e-11·|E|; individual power terms
// here are O(1–10) W, so 1e-6 separates "zero" from any wrong sign by five decades.
double energy_rate(const Model& model, double t) {
  const reference::OdeForm ode(model);
  reference::OdeForm::Scratch scratch = ode.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(ode.size()));
  std::vector<double> f(y.size());
  ode.pack(model.initial_state(), y.data());
  const LoadContext ctx{t, t};
  ode.rhs(ctx, y.data(), f.data(), scratch);
  const double eps = 1e-5;
  auto energy_at = [&](double s) {
    std::vector<double> z(y.size());
    for (std::size_t i = 0; i < y.size(); ++i) z[i] = y[i] + s * f[i];
    State state = model.initial_state();
    ode.unpack(ctx.t, z.data(), state);
    Workspace ws = model.make_workspace();
    return model.kinetic_energy(state) + model.potential_energy(ctx, state, ws);
  };
  return (energy_at(eps) - energy_at(-eps)) / (2.0 * eps);
}

TEST_CASE("energy is conserved by the equations of conservative models", "[core]") {
  // energy_rate's error, derived above it: 1e-6 W separates zero from any wrong term.
  CHECK(std::abs(energy_rate(testing::coulomb_wall_model(), 0.0)) < 1e-6);
  CHECK(std::abs(energy_rate(testing::heavy_top_model(), 0.0)) < 1e-6);
}

TEST_CASE("energy rate equals the power of the applied loads", "[core]") {
  // loaded_free_body: gravity (conservative) + body force at (1,0,0) + world torque pulse.
  // dE/dt = f·v_P + Γ·ω; at t = 0.05 the pulse is at its peak (sin² = 1).
  const Model model = testing::loaded_free_body_model();
  const double t = 0.05;
  const State s = model.initial_state();
  const Eigen::Matrix3d R = rotation::rotation_matrix(s[0].theta_WB);
  const Eigen::Vector3d p_BoP_B(1, 0, 0);
  const Eigen::Vector3d v_P =
      s[0].v_WBr + R * s[0].w_WB_B.cross(p_BoP_B - model.body(0).p_BoBr_B());
  const double power = (R * Eigen::Vector3d(1.0, 2.0, -0.5)).dot(v_P) +
                       Eigen::Vector3d(0.2, 0.0, 0.2).dot(R * s[0].w_WB_B);
  // Same derivation as above; the potential part (gravity) cancels.
  CHECK(energy_rate(model, t) == Approx(power).margin(1e-6));
}

TEST_CASE("angular momentum rate equals the moment of external loads", "[core]") {
  // dH_O/dt = Σ r × f + Σ Γ about the world origin. Torque-free: zero.
  const Model model = testing::loaded_free_body_model();
  const reference::OdeForm ode(model);
  reference::OdeForm::Scratch scratch = ode.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(ode.size())), f(y.size());
  const State s0 = model.initial_state();
  ode.pack(s0, y.data());
  const double t = 0.05;
  ode.rhs({t, t}, y.data(), f.data(), scratch);
  const double eps = 1e-5;
  auto h_at = [&](double sgn) {
    std::vector<double> z(y.size());
    for (std::size_t i = 0; i < y.size(); ++i) z[i] = y[i] + sgn * eps * f[i];
    State state = s0;
    ode.unpack(t, z.data(), state);
    return model.angular_momentum_W(state);
  };
  const Eigen::Vector3d dh = (h_at(1) - h_at(-1)) / (2 * eps);
  const Eigen::Matrix3d R = rotation::rotation_matrix(s0[0].theta_WB);
  const Body& b = model.body(0);
  const Eigen::Vector3d p_Wcm = s0[0].p_WBr;  // Br = Bcm for a free body
  const Eigen::Vector3d p_WP = p_Wcm + R * (Eigen::Vector3d(1, 0, 0) - b.p_BoBr_B());
  const Eigen::Vector3d f_body = R * Eigen::Vector3d(1.0, 2.0, -0.5);
  const Eigen::Vector3d moment = p_Wcm.cross(b.mass() * Eigen::Vector3d(0, 0, -9.81)) +
                                 p_WP.cross(f_body) + Eigen::Vector3d(0.2, 0.0, 0.2);
  // Central difference as above: O(ε²) ≈ 1e-10 relative to the O(10) moments.
  CHECK((dh - moment).norm() < 1e-6);
}

TEST_CASE("frame origin, reference point and velocities map consistently", "[core]") {
  const Model model = testing::loaded_free_body_model();
  const State s = model.initial_state();
  const auto& init = model.body(0).description().initial;
  // Bo → Br → Bo round trip (one rotation and back: a few ulp).
  CHECK((model.p_WBo(0, s[0]) - init.p_WBo).norm() < 1e-15);
  CHECK((model.v_WBo(0, s[0]) - init.v_WBo).norm() < 1e-14);
  // Linear momentum = m v_cm.
  CHECK((model.linear_momentum_W(s) - 2.5 * s[0].v_WBr).norm() < 1e-14);
}

TEST_CASE("pivot bodies use the inertia about the pivot", "[core]") {
  const Model model = testing::heavy_top_model();
  const Body& b = model.body(0);
  // I_pivot = I_C + m(|c|² I − c cᵀ) with c = (0, 1, 0): diag(15.234375, 0.46875, 15.234375).
  CHECK(b.I_Br_B()(0, 0) == Approx(15.234375).epsilon(1e-15));
  CHECK(b.I_Br_B()(1, 1) == Approx(0.46875).epsilon(1e-15));
  CHECK(b.I_Br_B()(2, 2) == Approx(15.234375).epsilon(1e-15));
  // Gravity torque about the pivot at identity: c × m g = (0,1,0) × (0,0,−147.15) = (−147.15,0,0).
  Workspace ws = model.make_workspace();
  const State s = model.initial_state();
  const Loads loads = model.compute_wrenches({0, 0}, s, ws);
  CHECK((ws.wrenches[0].tau_Br_W - Eigen::Vector3d(-147.15, 0, 0)).norm() < 1e-12);
  Accelerations acc(1);
  model.accelerations_from_wrenches(loads, ws, acc);
  CHECK(acc[0].a_WBr.norm() == 0.0);
}

TEST_CASE("compute_wrenches on given attitude matrices: the loads of A(θ), θ unread", "[core]") {
  // A body-frame force at a point, gravity about an off-centre origin and a world torque: each
  // wrench reads A. Given A(θ) itself the wrenches are compute_wrenches' to the bit, with the
  // state's θ unread (NaN here); given another attitude's matrix, they are that attitude's.
  const Model model = testing::loaded_free_body_model();
  const State s = model.initial_state();
  const LoadContext context{0.05, 0.0};  // inside the torque pulse
  Workspace ws = model.make_workspace();
  model.compute_wrenches(context, s, ws);
  const Wrench expected = ws.wrenches[0];
  State unread = s;
  unread[0].theta_WB.setConstant(std::numeric_limits<double>::quiet_NaN());
  const std::vector<Eigen::Matrix3d> A{rotation::rotation_matrix(s[0].theta_WB)};
  model.compute_wrenches(context, unread, A, ws);
  CHECK(ws.wrenches[0].f_W == expected.f_W);
  CHECK(ws.wrenches[0].tau_Br_W == expected.tau_Br_W);
  CHECK(ws.kinematics[0].R_WB == A[0]);
  // Another attitude: the body-frame force turns with it, so the wrench is not the first one.
  State turned = s;
  turned[0].theta_WB = Eigen::Vector4d(0.2, 0.9, 0.3, -0.1).normalized();
  model.compute_wrenches(context, turned, ws);
  const Wrench turned_expected = ws.wrenches[0];
  model.compute_wrenches(
      context, unread, std::vector<Eigen::Matrix3d>{rotation::rotation_matrix(turned[0].theta_WB)},
      ws);
  CHECK(ws.wrenches[0].f_W == turned_expected.f_W);
  CHECK(ws.wrenches[0].tau_Br_W == turned_expected.tau_Br_W);
  CHECK((turned_expected.f_W - expected.f_W).norm() > 0.1);
  // One matrix per body.
  CHECK_THROWS_AS(model.compute_wrenches(context, s, std::vector<Eigen::Matrix3d>{}, ws),
                  std::invalid_argument);
}

TEST_CASE("bodies reject unphysical data", "[core]") {
  RigidBodyDescription d;
  d.name = "b";
  d.mass = 0.0;
  CHECK_THROWS_AS(Body(d), std::invalid_argument);
  d.mass = 1.0;
  d.I_Bcm_B = Eigen::Vector3d(1.0, 1.0, 2.5).asDiagonal();  // 1 + 1 < 2.5
  CHECK_THROWS_WITH(Body(d), Catch::Contains("triangle"));
  d.I_Bcm_B = Eigen::Vector3d(1.0, 1.5, 2.5).asDiagonal();  // flat disk: J1 + J2 = J3 is fine
  CHECK_NOTHROW(Body(d));
  d.I_Bcm_B(0, 1) = 0.1;  // not symmetric
  CHECK_THROWS_WITH(Body(d), Catch::Contains("symmetric"));
  d.I_Bcm_B = Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal();
  CHECK_THROWS_WITH(Body(d), Catch::Contains("positive definite"));
  d.I_Bcm_B = Eigen::Matrix3d::Identity();
  d.initial.theta_WB = Eigen::Vector4d(1.0, 0.1, 0.0, 0.0);
  CHECK_THROWS_WITH(Body(d), Catch::Contains("unit"));
}

}  // namespace
}  // namespace flexref::core
