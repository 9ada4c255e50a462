/// \file mechanism_scenes_test.cpp
/// The bundled benchmark mechanisms on ideal joints (docs/joints.md, "Benchmark mechanisms")
/// against what is known of them independently: the driven slider-crank against its closed-form
/// kinematics and inverse dynamics, the double pendulum against its own two-degree-of-freedom
/// Lagrange equations, the four-bar's and the Bricard mechanism's energy, the four-bar's
/// reactions against its links' Newton–Euler balance, the Bricard
/// mechanism's redundant row, and a parallelogram four-bar driven into its dead point.
#include <boost/numeric/odeint.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "constraint/mobility.hpp"
#include "core/constrained_solve_tpl.hpp"
#include "core/error.hpp"
#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/newton_euler_balance.hpp"
#include "tests/support/solver_options.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::constraint {
namespace {

// The body's angle about +z from its Euler parameters (a planar body: θ = (cos φ/2, 0, 0,
// sin φ/2)), unwrapped to the branch nearest `near`.
double mechanism_angle_z(const core::BodyState& s, double near) {
  double phi = 2.0 * std::atan2(s.theta_WB(3), s.theta_WB(0));
  const double turn = 2.0 * std::numbers::pi;
  phi += turn * std::round((near - phi) / turn);
  return phi;
}

// The scene's reference trajectory by CVODE at rtol (atol = rtol) on its output grid.
reference::ReferenceRun mechanism_reference(const scene::Scene& scene, double rtol,
                                            const std::string& solver = "cvode") {
  return reference::solve_reference(solver, *scene.model,
                                    core::output_times(scene.end_time, scene.output_step),
                                    testing::with_rtol(rtol));
}

// Kinetic plus potential energy of a state.
double mechanism_energy(const core::Model& model, double t, const core::State& state) {
  core::Workspace ws = model.make_workspace();
  return model.kinetic_energy(state) + model.potential_energy({t, t}, state, ws);
}

// The largest position-level violation |Φ| over the joints (m or rad).
double mechanism_violation(const core::Model& model, double t, const core::State& state) {
  core::Workspace ws = model.make_workspace();
  double worst = 0.0;
  for (const auto& v : model.constraint_violations(t, state, ws)) worst = std::max(worst, v[0]);
  return worst;
}

// The rigid slider-crank with the crank driven at Ω (Simeon's data, scenes/slider_crank.toml):
// the closed-form kinematics and the driving torque from the power balance.
struct SliderCrankExact {
  double L1 = 0.15, L2 = 0.30, M2 = 0.151104, M3 = 0.075552, Omega = 150.0;
  double I2 = 0.0045339259 - 0.151104 * 0.15 * 0.15;  // rod about its centre of mass
  double phi2 = 0.0, x3 = 0.0, torque = 0.0;

  explicit SliderCrankExact(double t) {
    const double r = L1 / L2;
    const double s = std::sin(Omega * t);
    const double c = std::cos(Omega * t);
    const double s2 = -r * s;  // L1 sin φ1 + L2 sin φ2 = 0
    const double c2 = std::sqrt(1.0 - s2 * s2);
    phi2 = std::asin(s2);
    x3 = L1 * c + L2 * c2;
    // Rates: differentiate L2 sin φ2 = −L1 sin Ωt once and twice.
    const double w2 = -r * Omega * c / c2;
    const double a2 = (r * Omega * Omega * s + s2 * w2 * w2) / c2;
    const double v3 = -L1 * Omega * s - L2 * s2 * w2;
    const double a3 = -L1 * Omega * Omega * c - L2 * c2 * w2 * w2 - L2 * s2 * a2;
    // The rod's centre of mass G = P + (L2/2) e(φ2), its velocity and acceleration.
    const double vx = -L1 * Omega * s - 0.5 * L2 * w2 * s2;
    const double vy = L1 * Omega * c + 0.5 * L2 * w2 * c2;
    const double ax = -L1 * Omega * Omega * c + 0.5 * L2 * (-a2 * s2 - w2 * w2 * c2);
    const double ay = -L1 * Omega * Omega * s + 0.5 * L2 * (a2 * c2 - w2 * w2 * s2);
    // Power balance: only the drive does work (no gravity, ideal joints), and the crank's own
    // kinetic energy is constant, so τ Ω = d/dt(T_rod + T_slider).
    const double power = M2 * (vx * ax + vy * ay) + I2 * w2 * a2 + M3 * v3 * a3;
    torque = power / Omega;
  }
};

}  // namespace

TEST_CASE("slider-crank: the driven mechanism follows its closed-form kinematics and torque",
          "[constraint][mechanisms]") {
  const scene::Scene scene = scene::read_scene("scenes/slider_crank.toml");
  const core::Model& model = *scene.model;
  // The closed form agrees with the IVP test set's multiplier at t = 0.1 (−λ3, the test set's
  // sign convention M w + Gᵀλ = F): its value is printed to 8 digits there.
  CHECK(std::abs(SliderCrankExact(0.1).torque - -25.01465778) < 1e-8);
  const double rtol = 1e-10;
  const reference::ReferenceRun run = mechanism_reference(scene, rtol);
  const int rod = model.body_index("rod");
  const int slider = model.body_index("slider");
  const int drive = 0;  // joint O, the first in the scene
  REQUIRE(model.constraints()->joint_name(drive) == "O");
  core::Workspace ws = model.make_workspace();
  double worst_x = 0.0, worst_phi = 0.0, worst_torque = 0.0;
  for (std::size_t k = 0; k < run.trajectory.times.size(); ++k) {
    const double t = run.trajectory.times[k];
    const core::State& s = run.trajectory.states[k];
    const SliderCrankExact exact(t);
    worst_x = std::max(
        worst_x, std::abs(model.p_WBo(slider, s[static_cast<std::size_t>(slider)]).x() - exact.x3));
    worst_phi = std::max(
        worst_phi,
        std::abs(mechanism_angle_z(s[static_cast<std::size_t>(rod)], exact.phi2) - exact.phi2));
    const std::vector<core::JointReaction> reactions = model.joint_reactions({t, t}, s, ws);
    worst_torque = std::max(worst_torque, std::abs(reactions[drive].tau_W.z() - exact.torque));
  }
  INFO("largest errors: slider " << worst_x << " m, rod angle " << worst_phi
                                 << " rad, driving torque " << worst_torque << " N m");
  // The motion is kinematic: the state is the drive's law through the constraints, so the
  // positions err only by what the solver lets the local errors accumulate. Per step the error
  // is below rtol × |y| (|y| ≤ 150 for the rates, ≤ 15 rad for the crank angle), and the
  // Baumgarte term pulls the drift back onto the manifold at rate α, so the error stays a few
  // local tolerances: 100 × rtol × 15 = 1.5e-7 rad for the angle, and × L1 + L2 = 0.45 m for the
  // slider, a margin of a few 10 over what is measured (the INFO line).
  CHECK(worst_phi < 100 * rtol * 15.0);
  CHECK(worst_x < 100 * rtol * 15.0 * 0.45);
  // The torque is the accelerations' (Ω² L ~ 3e3 m/s²) image through the masses: its error is
  // the positions' relative error (1.5e-7 / 0.45 at most) times the largest torque, 69.8 N·m
  // over the cycle, plus the rates' error (100 rtol relative): 70 × 5e-7 = 3.5e-5 N·m.
  CHECK(worst_torque < 70.0 * 5e-7);
}

TEST_CASE("slider-crank and Bricard: degrees of freedom by counting and in fact",
          "[constraint][mechanisms]") {
  SECTION("slider-crank: three out-of-plane rows repeat in the planar loop") {
    const Mobility m = mobility(*scene::read_scene("scenes/slider_crank.toml").model);
    CHECK(m.coordinates == 18);  // three free bodies
    CHECK(m.rows == 21);         // revolute 5 (+1 driven) × 3, prismatic 5
    CHECK(m.rank == 18);
    CHECK(m.by_counting() == -3);
    CHECK(m.in_fact() == 0);  // kinematic: the drive fixes the motion
    CHECK(m.redundant.size() == 3);
  }
  SECTION("Bricard: 0 by counting, 1 in fact, one redundant row") {
    const Mobility m = mobility(*scene::read_scene("scenes/bricard.toml").model);
    CHECK(m.coordinates == 30);
    CHECK(m.rows == 30);
    CHECK(m.by_counting() == 0);
    CHECK(m.in_fact() == 1);
    REQUIRE(m.redundant.size() == 1);
    CHECK(!m.redundant[0].joint.empty());
    CHECK(!m.redundant[0].label.empty());
  }
  SECTION("double pendulum: an open chain has no redundant row") {
    const Mobility m = mobility(*scene::read_scene("scenes/double_pendulum_ideal.toml").model);
    CHECK(m.in_fact() == 2);
    CHECK(m.by_counting() == 2);
    CHECK(m.redundant.empty());
  }
  SECTION("row labels follow the rows' order") {
    CHECK(row_label(JointType::kRevolute, true, 5) == "drive (angle about Z_b)");
    CHECK(row_label(JointType::kPrismatic, false, 4) == "no twist X_b.Y_a = 0");
    CHECK_THROWS_AS(row_label(JointType::kDistance, false, 1), std::out_of_range);
  }
}

TEST_CASE("four-bar: a Grashof crank-rocker under gravity conserves its energy",
          "[constraint][mechanisms]") {
  const scene::Scene scene = scene::read_scene("scenes/four_bar.toml");
  const core::Model& model = *scene.model;
  const double rtol = 1e-10;
  // Outputs at half the scene's step, for the reactions' check below.
  const reference::ReferenceRun run = reference::solve_reference(
      "cvode", model, core::output_times(scene.end_time, scene.output_step / 2.0),
      testing::with_rtol(rtol));
  const double e0 = mechanism_energy(model, 0.0, run.trajectory.states.front());
  double drift = 0.0;
  for (std::size_t k = 0; k < run.trajectory.times.size(); ++k) {
    const double t = run.trajectory.times[k];
    drift = std::max(drift, std::abs(mechanism_energy(model, t, run.trajectory.states[k]) - e0));
  }
  // The reactions at every output, as `flexref reference` writes them (the table's J.fx …
  // J.tz), through the re-selection of the rows at t ≈ 1.848 (the rows kept at the start
  // become dependent among themselves while all rows keep their rank: not a singular
  // configuration), against each link's Newton–Euler balance with the accelerations from the
  // output's velocities (tests/support/newton_euler_balance.hpp). Its error is the
  // differences' truncation, h⁴ f⁽⁵⁾/30 inside: the links turn at ≤ 23 rad/s, but near t = 1.87
  // the coupler's force rises from 8 to 100 N within 0.07 s, and there the residual scales as
  // h⁴ with an effective rate ω ≈ 170 1/s (2.6e-5 at h = 1e-3, independent of rtol from 1e-10
  // to 1e-12): (hω)⁴/30 = 1.7e-6 at h = 5e-4. The velocities' noise, 10.7 × 10 rtol / (hω),
  // is ≤ 1e-6. 1e-5 bounds both; a reaction paired with the wrong row after the re-selection,
  // or a joint's torque about the wrong point, is off by O(1).
  const trajectory::TrajectoryTable table = trajectory::tabulate(model, run.trajectory);
  const testing::NewtonEulerResidual balance =
      testing::newton_euler_residual(model, run.trajectory, table);
  INFO("force residual " << balance.force << " (" << balance.force_at << "), torque residual "
                         << balance.torque << " (" << balance.torque_at << ")");
  CHECK(balance.rows == run.trajectory.times.size());
  CHECK(balance.force <= 1e-5);
  CHECK(balance.torque <= 1e-5);
  const double t_end = run.trajectory.times.back();
  const double violation = mechanism_violation(model, t_end, run.trajectory.states.back());
  INFO("energy " << e0 << " J, largest drift " << drift << " J, final violation " << violation);
  // E ≈ 3.1 J is a sum of terms up to the kinetic energy's ~3 J; each state component errs by a
  // few rtol relative over the horizon, so E by ~1e3 rtol × 3 J with the accumulation over
  // ~1e4 steps: 3e-6 J bounds it with margin (measured: the INFO line).
  CHECK(drift < 1e4 * rtol * 3.0);
  // The stabilized index-1 form keeps Φ at the size of the local errors: 100 rtol × 1 m.
  CHECK(violation < 100 * rtol);
  // The crank turns fully, as the scene's header says: its rate never falls to zero (measured
  // 9.8 to 23 rad/s), so over 2 s it turns by more than ω_min × 2 s > 2π.
  double omega_min = 1e300;
  for (const core::State& s : run.trajectory.states)
    omega_min = std::min(omega_min, s[0].w_WB_B.z());
  CHECK(omega_min * t_end > 2.0 * std::numbers::pi);
}

TEST_CASE("four-bar: a parallelogram driven into its dead point is reported, not integrated",
          "[constraint][mechanisms][long]") {
  // IFToMM A02 with N = 1: cranks A-B and D-C of 1 m, vertical at t = 0, the coupler B-C
  // horizontal; the crank at A driven clockwise at 1 rad/s, so all links are collinear (the
  // mechanism's change point, where J M⁻¹ Jᵀ loses rank) at t = π/2.
  std::string text = "[scene]\nname = \"parallelogram\"\nend_time = 2.0\noutput_step = 0.01\n";
  const auto rod = [](const std::string& name, const std::string& at, bool upright) {
    // Upright: turned by π/2 about +z, θ = (cos π/4, 0, 0, sin π/4) to 17 digits.
    return "[[body]]\nname = \"" + name + "\"\nmass = 1.0\ninertia = [1e-4, 0.0833333333333, " +
           "0.0833333333333]\ncenter_of_mass = [0.5, 0.0, 0.0]\nposition = " + at +
           (upright ? "\norientation = [0.70710678118654757, 0.0, 0.0, 0.70710678118654757]\n"
                    : "\n");
  };
  text += rod("left", "[0.0, 0.0, 0.0]", true) + "angular_velocity = [0.0, 0.0, -1.0]\n";
  text += rod("coupler", "[0.0, 1.0, 0.0]", false) + "velocity = [1.0, 0.0, 0.0]\n";
  text += rod("right", "[1.0, 0.0, 0.0]", true) + "angular_velocity = [0.0, 0.0, -1.0]\n";
  const auto joint = [](const std::string& name, const std::string& a, const std::string& pa,
                        const std::string& b, const std::string& pb, const std::string& extra) {
    return "[[joint]]\nname = \"" + name +
           "\"\nmodel = \"ideal\"\nkind = \"revolute\"\nbody_a = \"" + a + "\"\npoint_a = " + pa +
           "\nbody_b = \"" + b + "\"\npoint_b = " + pb +
           "\naxis_a = [0.0, 0.0, 1.0]\naxis_b = [0.0, 0.0, 1.0]\n" + extra;
  };
  text += joint("A", "left", "[0.0, 0.0, 0.0]", "ground", "[0.0, 0.0, 0.0]",
                "drive = { law = \"constant-rate\", rate = -1.0 }\n");
  text += joint("B", "coupler", "[0.0, 0.0, 0.0]", "left", "[1.0, 0.0, 0.0]", "");
  text += joint("C", "coupler", "[1.0, 0.0, 0.0]", "right", "[1.0, 0.0, 0.0]", "");
  text += joint("D", "right", "[0.0, 0.0, 0.0]", "ground", "[1.0, 0.0, 0.0]", "");
  const scene::Scene scene = scene::parse_scene(text, "parallelogram.toml");
  // IDA integrates the GGL form, whose residual never factors J M⁻¹ Jᵀ: its root function
  // checks every step's configuration instead (reference/ida_solver.cpp).
  for (const std::string solver : {"cvode", "odeint", "arkode", "ida"}) {
    INFO("solver " << solver);
    std::string message;
    try {
      (void)mechanism_reference(scene, 1e-8, solver);
    } catch (const core::SolverError& e) {
      message = e.what();
    }
    INFO("message: " << message);
    REQUIRE(!message.empty());  // a trajectory through the dead point would be garbage
    CHECK_THAT(message, Catch::Matchers::Contains("joint '"));
    const auto near = message.find("singular configuration at t = ");
    if (near != std::string::npos) {
      // Stopped on the approach (CVODE: its fixed-point iteration stalls before the dead point,
      // Newton restarts there and evaluates within the pivot test's reach of it, |Δt| ~ 1e-4
      // measured): the time must be the dead point's to within the pivot test's ~1e-3.
      double t = 0.0;
      REQUIRE(std::sscanf(message.c_str() + near, "singular configuration at t = %lf", &t) == 1);
      CHECK(std::abs(t - std::numbers::pi / 2.0) < 1e-3);
      continue;
    }
    CHECK_THAT(message, Catch::Matchers::Contains("singular configuration passed between t = "));
    // The two solves the orientation test compares bracket the dead point: read them back.
    const auto at = message.find("between t = ");
    REQUIRE(at != std::string::npos);
    double t0 = 0.0, t1 = 0.0;
    REQUIRE(std::sscanf(message.c_str() + at, "between t = %lf and t = %lf", &t0, &t1) == 2);
    CHECK(t0 <= std::numbers::pi / 2.0);
    CHECK(t1 >= std::numbers::pi / 2.0);
    // Between two evaluations of one step (steps near π/2 are < 0.2 s at rtol 1e-8, measured
    // 0.03 to 0.08).
    CHECK(t1 - t0 < 0.2);
  }
}

TEST_CASE("double pendulum: the jointed reference solves the pendulum's own Lagrange equations",
          "[constraint][mechanisms]") {
  const scene::Scene scene = scene::read_scene("scenes/double_pendulum_ideal.toml");
  const double rtol = 1e-10;
  const reference::ReferenceRun run = mechanism_reference(scene, rtol);
  // Absolute angles θ1, θ2 from the downward vertical (rod direction (sin θ, −cos θ)): two
  // uniform rods m, L, I = m L²/12 about their centres, hinged at their ends, gravity g along −y.
  const double m = 1.0, L = 1.0, g = 9.81, I = m * L * L / 12.0;
  using Vector = std::vector<double>;
  const auto lagrange = [&](const Vector& y, Vector& dy, double) {
    const double c = std::cos(y[0] - y[1]);
    const double s = std::sin(y[0] - y[1]);
    const double m11 = I + m * L * L / 4.0 + m * L * L;
    const double m12 = 0.5 * m * L * L * c;
    const double m22 = I + m * L * L / 4.0;
    const double f1 = -0.5 * m * L * L * s * y[3] * y[3] - 1.5 * m * g * L * std::sin(y[0]);
    const double f2 = 0.5 * m * L * L * s * y[2] * y[2] - 0.5 * m * g * L * std::sin(y[1]);
    const double det = m11 * m22 - m12 * m12;
    dy[0] = y[2];
    dy[1] = y[3];
    dy[2] = (m22 * f1 - m12 * f2) / det;
    dy[3] = (m11 * f2 - m12 * f1) / det;
  };
  namespace odeint = boost::numeric::odeint;
  Vector y{std::numbers::pi / 2.0, std::numbers::pi / 2.0, 0.0, 0.0};  // horizontal, at rest
  std::vector<Vector> lagrange_states;
  const double tight = 1e-13;  // 1000 × below the reference's rtol: its error does not count
  odeint::integrate_times(
      odeint::make_controlled(tight, tight, odeint::runge_kutta_fehlberg78<Vector>()), lagrange, y,
      run.trajectory.times.begin(), run.trajectory.times.end(), 1e-4,
      [&](const Vector& x, double) { lagrange_states.push_back(x); });
  REQUIRE(lagrange_states.size() == run.trajectory.times.size());
  double worst = 0.0;
  double worst_time = 0.0;
  for (std::size_t k = 0; k < run.trajectory.times.size(); ++k) {
    const core::State& s = run.trajectory.states[k];
    for (int b = 0; b < 2; ++b) {
      // The rod's body x axis is at φ = θ − π/2 from +x.
      const double theta_exact = lagrange_states[k][static_cast<std::size_t>(b)];
      const double theta =
          mechanism_angle_z(s[static_cast<std::size_t>(b)], theta_exact - std::numbers::pi / 2.0) +
          std::numbers::pi / 2.0;
      if (std::abs(theta - theta_exact) > worst) {
        worst = std::abs(theta - theta_exact);
        worst_time = run.trajectory.times[k];
      }
    }
  }
  INFO("largest angle difference " << worst << " rad at t = " << worst_time);
  // Both solve the same motion; the difference is the reference's global error (the Lagrange
  // solution's, at 1e-13, is 1000 × smaller). Its local errors are rtol × |y| (|y| ≲ 10 for the
  // rates); the chaotic flow amplifies them by e^(λT), λ of order 1/s at this energy, so ~10
  // over 2 s, and ~1e2 steps accumulate them: 1e3 × rtol × 10 = 1e-6 rad. Measured 6.4e-9 rad
  // (the INFO line).
  CHECK(worst < 1e3 * rtol * 10.0);
}

TEST_CASE("Bricard mechanism: energy constant to 1e-9 relative over 10 s, joints kept",
          "[constraint][mechanisms]") {
  const scene::Scene scene = scene::read_scene("scenes/bricard.toml");
  const core::Model& model = *scene.model;
  const double rtol = 1e-11;
  const reference::ReferenceRun run = mechanism_reference(scene, rtol);
  const double e0 = mechanism_energy(model, 0.0, run.trajectory.states.front());
  // The mechanical energy at rest, Σ m g y_cm = −9.81 (0 − 0.5 − 1 − 1 − 0.5) = −29.43 J.
  CHECK(std::abs(e0 - -29.43) < 1e-12 * 29.43 * 10);  // sums of 5 terms: round-off
  double drift = 0.0;
  for (std::size_t k = 0; k < run.trajectory.times.size(); ++k) {
    drift = std::max(
        drift,
        std::abs(mechanism_energy(model, run.trajectory.times[k], run.trajectory.states[k]) - e0));
  }
  const double violation =
      mechanism_violation(model, run.trajectory.times.back(), run.trajectory.states.back());
  INFO("largest energy drift " << drift << " J (relative " << drift / std::abs(e0)
                               << "), final violation " << violation);
  // The criterion: constant to 1e-9 relative over the horizon.
  CHECK(drift < 1e-9 * std::abs(e0));
  // Φ stays at the size of the local errors: 100 rtol × the 1 m links.
  CHECK(violation < 100 * rtol);
  // It moves from rest (the gravity force along the mobility is not zero): rod1's centre of
  // mass swings from (0.5, 0, 0) through the x < 0 half of its circle about the y axis (it
  // returns near the start after 5 s and 10 s: the motion is periodic).
  const int rod1 = model.body_index("rod1");
  double x_min = 1.0;
  for (const core::State& s : run.trajectory.states) {
    x_min = std::min(x_min, s[static_cast<std::size_t>(rod1)].p_WBr.x());
  }
  CHECK(x_min < -0.4);
}

}  // namespace flexref::constraint

namespace flexref::constraint {
namespace {

TEST_CASE("Bricard mechanism: IDA and Odeint keep their accuracy through the rows chosen again",
          "[constraint][mechanisms]") {
  // The Bricard linkage's independent rows are chosen again near t = 1.05 s (docs/decisions.md,
  // "Model, Workspace, tracker"). Where a trial point's rows were kept for the integration (IDA)
  // or a step's stages each chose rows of their own (Odeint before kChooseRows), the error grew
  // past its tolerance there: IDA at rtol 1e-8 8.0e-7 m, Odeint at rtol 1e-9 1.4e-8 m; and where
  // a 0.12 s step's later stages chose rows its first stages had not (Odeint at rtol 1e-8, before
  // the step was taken again on rows chosen at its start), 6.7e-7 m. Bound: 10 × rtol × the 1 m
  // links over the 10 s (measured now: 1.3e-10 m, 3.3e-9 m and 2.6e-8 m). The check is CVODE at
  // rtol 1e-12 (2e-11 m from CVODE at 1e-13), far below the bounds.
  const scene::Scene scene = scene::read_scene("scenes/bricard.toml");
  const reference::ReferenceRun check = mechanism_reference(scene, 1e-12);
  const auto largest_position_error = [&](const reference::ReferenceRun& run) {
    REQUIRE(run.trajectory.states.size() == check.trajectory.states.size());
    double worst = 0.0;
    for (std::size_t k = 0; k < run.trajectory.states.size(); ++k) {
      for (std::size_t b = 0; b < run.trajectory.states[k].size(); ++b) {
        worst = std::max(worst,
                         (run.trajectory.states[k][b].p_WBr - check.trajectory.states[k][b].p_WBr)
                             .lpNorm<Eigen::Infinity>());
      }
    }
    return worst;
  };
  for (const auto& [solver, rtol] :
       {std::pair<std::string, double>{"ida", 1e-8}, {"odeint", 1e-9}, {"odeint", 1e-8}}) {
    INFO(solver << " at rtol " << rtol);
    const double error = largest_position_error(mechanism_reference(scene, rtol, solver));
    INFO("largest position error " << error << " m");
    CHECK(error < 10 * rtol * 1.0);
  }
}

}  // namespace
}  // namespace flexref::constraint
