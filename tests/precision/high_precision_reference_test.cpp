/// \file high_precision_reference_test.cpp
/// References in extended and quad precision (precision/, docs/precision.md): the generic model
/// against core::Model (the same equations, its own state and data), an exact solution in closed
/// form, conservation laws, the ordering double < extended < quad with honest estimates,
/// load switches, and the scenes it carries (all) and the tolerances it refuses.
#include "precision/high_precision_reference.hpp"

// Eigen's NumTraits for float128 before any Eigen type of it.
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "precision/ode_system.hpp"
#include "reference/exact_rotation_tpl.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"
#include "tests/precision/precision_order.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

/// A body that exercises every term: pivot off the centre of mass or free, gravity, a world
/// torque with a sin² pulse, a body-frame force at a point with a rectangular pulse.
scene::SceneSpec loaded_spec(bool pivot) {
  scene::SceneSpec spec = spec_of("scenes/free_spin.toml");
  spec.end_time = 1.0;
  spec.output_step = 0.1;
  spec.g_W = Eigen::Vector3d(0.3, -1.1, -9.81);
  core::RigidBodyDescription& d = spec.bodies[0].description;
  d.I_Bcm_B << 3.0, 0.2, -0.1, 0.2, 4.0, 0.3, -0.1, 0.3, 5.0;
  d.p_BoBcm_B = Eigen::Vector3d(0.1, 0.4, -0.2);
  d.initial.theta_WB = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
  d.initial.v_WBo = Eigen::Vector3d(0.5, -0.2, 1.0);
  if (pivot) {
    d.motion = core::MotionKind::kPivot;
    d.p_BoPivot_B = Eigen::Vector3d(-0.3, 0.2, 0.5);
    d.initial.v_WBo.setZero();
  }
  scene::LoadSpec torque;
  torque.torque = true;
  torque.value = Eigen::Vector3d(0.2, -0.4, 0.7);
  torque.frame = core::LoadFrame::kWorld;
  torque.profile = core::TimeProfile::sin2_pulse(0.0, 0.5);
  scene::LoadSpec force;
  force.value = Eigen::Vector3d(-1.0, 2.0, 0.5);
  force.frame = core::LoadFrame::kBody;
  force.p_BoP_B = Eigen::Vector3d(0.7, -0.2, 0.1);
  force.profile = core::TimeProfile::rectangular_pulse(0.2, 0.5);
  spec.loads = {torque, force};
  return spec;
}

TEST_CASE("the generic model agrees with core::Model at random states", "[precision]") {
  // core::Model and OdeSystemTpl<double> run the same elements and body rows on their own
  // state layouts and body data (formed in S by the latter): a layout or data error shows up
  // as an O(1) difference. Tolerance: both are a few dozen flops from the same inputs, 1e-12
  // relative.
  for (const bool pivot : {false, true}) {
    const scene::SceneSpec spec = loaded_spec(pivot);
    const core::Model model = scene::build_model(spec);
    const OdeSystemTpl<double> tpl(spec, core::FlexibleFormulation::kCoupled);
    core::Workspace ws = model.make_workspace();
    core::Accelerations acc = model.make_accelerations();
    std::vector<double> y = tpl.initial_state();
    std::vector<double> dydt(y.size());
    // The body's blocks in y (reference/form_layout.hpp: a pivot has no p and v blocks).
    const reference::BodyBlock& block = tpl.blocks().front();
    REQUIRE((block.p >= 0) == !pivot);
    const auto at = [](int offset, int k) { return static_cast<std::size_t>(offset + k); };
    for (const double t : {0.05, 0.3, 0.6}) {
      // Perturb the state away from the initial one (unit θ, nonzero velocities).
      y[at(block.w, 0)] += 0.3 * t;
      y[at(block.w, 1)] -= 0.5;
      y[at(block.w, 2)] += 0.2;
      core::State state = model.initial_state();
      if (block.p >= 0) {
        state[0].p_WBr = Eigen::Vector3d(y[at(block.p, 0)], y[at(block.p, 1)], y[at(block.p, 2)]);
        state[0].v_WBr = Eigen::Vector3d(y[at(block.v, 0)], y[at(block.v, 1)], y[at(block.v, 2)]);
      }
      state[0].theta_WB = Eigen::Vector4d(y[at(block.theta, 0)], y[at(block.theta, 1)],
                                          y[at(block.theta, 2)], y[at(block.theta, 3)]);
      state[0].w_WB_B = Eigen::Vector3d(y[at(block.w, 0)], y[at(block.w, 1)], y[at(block.w, 2)]);
      model.compute_accelerations(core::LoadContext{t, t}, state, ws, acc);
      tpl.derivative(y, dydt, t, t);
      CAPTURE(pivot, t);
      for (int k = 0; k < 3; ++k) {
        CHECK(dydt[at(block.w, k)] == Approx(acc[0].alpha_WB_B(k)).epsilon(1e-12).margin(1e-12));
        if (block.v >= 0) {
          CHECK(dydt[at(block.v, k)] == Approx(acc[0].a_WBr(k)).epsilon(1e-12).margin(1e-12));
        }
      }
      // The output row (Bo, points, energy) is the double tabulation's.
      core::Trajectory trajectory;
      trajectory.times = {t};
      trajectory.states = {state};
      const trajectory::TrajectoryTable table = trajectory::tabulate(model, trajectory);
      const std::vector<double> row = tpl.output_row(t, y);
      REQUIRE(row.size() + 1 == table.columns.size());
      for (std::size_t c = 0; c < row.size(); ++c) {
        CAPTURE(table.columns[c + 1]);
        CHECK(row[c] == Approx(table.rows[0][c + 1]).epsilon(1e-12).margin(1e-12));
      }
    }
  }
}

/// The axisymmetric torque-free body in closed form (J1 = J2): θ(t) = q_L(Ω_p t) ⊗ θ0 ⊗
/// q_3(Ω_r t), a rotation at Ω_p = |L|/J1 about the fixed momentum direction composed with one
/// at Ω_r = (J1 − J3) ω3/J1 about the symmetry axis (Landau–Lifshitz §33), ω̄(t) = A(t)ᵀ L/J1 +
/// Ω_r e3. Only sin and cos: exact in any precision.
template <typename S>
std::vector<S> symmetric_top(const std::vector<S>& y0, S J1, S J3, S t) {
  using std::cos;
  using std::sin;
  using Quaternion = reference::detail::Quaternion<S>;
  using Vector3 = reference::detail::Vector3<S>;
  const Quaternion q0(y0[3], y0[4], y0[5], y0[6]);
  const Vector3 w0(y0[10], y0[11], y0[12]);
  const Vector3 L = rotation::rotation_matrix<S>(q0) * Vector3(J1 * w0(0), J1 * w0(1), J3 * w0(2));
  const S norm = L.norm();
  const S wp = norm / J1;
  const S wr = (J1 - J3) * w0(2) / J1;
  const S hp = wp * t / S(2), hr = wr * t / S(2);
  Quaternion qL;
  qL << cos(hp), (sin(hp) / norm) * L;
  const Quaternion q3(cos(hr), S(0), S(0), sin(hr));
  const Quaternion q = reference::detail::quaternion_multiply<S>(
      reference::detail::quaternion_multiply<S>(qL, q0), q3);
  const Vector3 Lb = rotation::rotation_matrix<S>(q).transpose() * L;
  return {q(0), q(1), q(2), q(3), Lb(0) / J1, Lb(1) / J1, Lb(2) / J1 + wr};
}

template <typename S>
S parse(const std::string& text) {
  if constexpr (std::is_same_v<S, long double>) {
    return std::strtold(text.c_str(), nullptr);
  } else {
    return S(text);
  }
}

template <typename S>
double worst_error(const HighPrecisionRun& run, const std::vector<double>& times, S J1, S J3,
                   const std::vector<S>& y0) {
  using std::abs;
  S worst(0);
  for (std::size_t r = 0; r < times.size(); ++r) {
    const std::vector<S> exact = symmetric_top(y0, J1, J3, S(times[r]));
    // Row layout: x y z e0..e3 vx vy vz W1 W2 W3 …: θ at 3..6, ω̄ at 10..12.
    for (std::size_t k = 0; k < 4; ++k) {
      worst = std::max(worst, S(abs(parse<S>(run.text[r][3 + k]) - exact[k])));
    }
    for (std::size_t k = 0; k < 3; ++k) {
      worst = std::max(worst, S(abs(parse<S>(run.text[r][10 + k]) - exact[4 + k])) / S(2));
    }
  }
  return static_cast<double>(worst);
}

TEST_CASE("quad and extended against the closed-form symmetric top", "[precision]") {
  scene::SceneSpec spec = spec_of("scenes/free_spin.toml");
  spec.end_time = 20.0;
  spec.output_step = 0.1;
  core::RigidBodyDescription& d = spec.bodies[0].description;
  d.I_Bcm_B = Eigen::Vector3d(3.0, 3.0, 5.0).asDiagonal();
  d.initial.theta_WB = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  // Errors of θ (unit) and ω̄/|ω̄| (|ω̄| = 2.03): relative to the solution's size. Quad: 1e-25
  // is the bound (rtol 1e-28 leaves 1000× for the growth over 200 outputs); extended:
  // 1e-15 (rtol 1e-16, ε 5.4e-20).
  const HighPrecisionRun quad = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  const OdeSystemTpl<Quad> mq(spec, core::FlexibleFormulation::kCoupled);
  CHECK(worst_error<Quad>(quad, times, Quad(3), Quad(5), mq.initial_state()) < 1e-25);
  const HighPrecisionRun ext = solve_high_precision(spec, times, Precision::kExtended, 1e-16);
  const OdeSystemTpl<long double> me(spec, core::FlexibleFormulation::kCoupled);
  CHECK(worst_error<long double>(ext, times, 3.0L, 5.0L, me.initial_state()) < 1e-15);
}

TEST_CASE("quad conserves energy and angular momentum on free_spin and the heavy top",
          "[precision]") {
  // Torque-free: E and the world momentum are invariants; heavy top: E and L_z (vertical, about
  // the pivot) and L_3 (symmetry axis). Quad at rtol 1e-28: drift ≤ 1e-26 relative.
  const scene::SceneSpec spec = spec_of("scenes/free_spin.toml");
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  const std::size_t energy = run.text.front().size() - 1;
  const Quad e0(run.text.front()[energy]);
  Quad worst(0);
  for (const auto& row : run.text) worst = std::max(worst, Quad(abs(Quad(row[energy]) - e0) / e0));
  CHECK(static_cast<double>(worst) < 1e-26);

  const scene::SceneSpec top = spec_of("scenes/heavy_top.toml");
  const std::vector<double> top_times = core::output_times(top.end_time, top.output_step);
  const HighPrecisionRun top_run = solve_high_precision(top, top_times, Precision::kQuad, 1e-28);
  const Quad top_e0(top_run.text.front()[top_run.text.front().size() - 1]);
  Quad top_worst(0);
  for (const auto& row : top_run.text) {
    top_worst = std::max(top_worst, Quad(abs(Quad(row.back()) - top_e0) / abs(top_e0)));
  }
  CHECK(static_cast<double>(top_worst) < 1e-26);
}

TEST_CASE("double, extended and quad agree in that order with honest estimates",
          "[precision][long_quad]") {
  // The rigid scenes whose quad references take seconds, over their first 2 s (the whole
  // horizons: tests/precision/precision_order_study_test.cpp, label study).
  for (const char* file : kFastRigidScenes) check_precision_order(file, 2.0);
}

TEST_CASE("a reference over its wall-time budget stops early and says its projection",
          "[precision]") {
  scene::SceneSpec spec = spec_of("scenes/free_spin.toml");
  spec.end_time = 1.0;
  spec.output_step = 0.1;
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  // A budget of 1e-300 s, which no run keeps to at any speed of the machine: projections start
  // once 1 % of it has elapsed, i.e. at the first check (after 64 evaluations, well before the
  // first output at t = 0.1), and project more than it; a guard that only looked at the end
  // would run to t = 1. The verdict does not depend on the clock's readings, only on time
  // passing at all between the start and the 64th evaluation.
  try {
    (void)certified_high_precision_reference(spec, times, Precision::kQuad, 1e-28, "rotation",
                                             nullptr, core::FlexibleFormulation::kCoupled, 1e-300);
    FAIL("a quad reference finished within 1e-300 s");
  } catch (const BudgetExceeded& e) {
    CHECK(e.budget_seconds() == 1e-300);
    CHECK(e.projected_seconds() > 1e-300);
    CHECK(e.reached_time() < 0.1);
    CHECK(std::string(e.what()).find("over its budget of 1e-300 s") != std::string::npos);
  }
  // A budget the reference keeps to at any speed of the machine (1e300 s) leaves it bit for
  // bit as without one.
  HighPrecisionRun bounded;
  HighPrecisionRun free_run;
  const auto with =
      certified_high_precision_reference(spec, times, Precision::kExtended, 1e-16, "rotation",
                                         &bounded, core::FlexibleFormulation::kCoupled, 1e300);
  const auto without =
      certified_high_precision_reference(spec, times, Precision::kExtended, 1e-16, "rotation",
                                         &free_run, core::FlexibleFormulation::kCoupled, 0.0);
  CHECK(bounded.text == free_run.text);
  CHECK(with.estimate.value == without.estimate.value);
}

TEST_CASE("every scene is carried in extended/quad, a tolerance beyond it is refused",
          "[precision]") {
  const auto message = [](const scene::SceneSpec& scene) {
    try {
      check_supported(scene);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  for (const char* file : {"scenes/tube_support_impact.toml", "scenes/coulomb_wall.toml",
                           "scenes/double_pendulum_impacts.toml", "scenes/bouncing_ball.toml",
                           "scenes/flexible_spinner.toml", "scenes/spin_up_beam_stiff_2.toml",
                           "scenes/free_spin.toml", "scenes/pendulum_on_sliding_support.toml"}) {
    CAPTURE(file);
    CHECK(message(spec_of(file)) == "accepted");
  }
  // A flexible body with another body, a sphere–sphere pair between them and a joint
  // (precision/ode_system.hpp; multibody_model_test.cpp checks what it computes).
  scene::SceneSpec two = spec_of("scenes/flexible_spinner.toml");
  two.bodies.push_back(spec_of("scenes/free_spin.toml").bodies.front());
  CHECK(message(two) == "accepted");
  scene::SceneSpec sphere = two;
  sphere.contacts.push_back(spec_of("scenes/bouncing_ball.toml").contacts.front());
  sphere.contacts.front().pairs.front().kind = contact::ContactPair::Kind::kSphereSphere;
  sphere.contacts.front().pairs.front().body_a = 1;
  CHECK(message(sphere) == "accepted");
  scene::SceneSpec joint = spec_of("scenes/flexible_spinner.toml");
  joint.joints.push_back(spec_of("scenes/double_pendulum_impacts.toml").joints.front());
  joint.joints.front().a.body = 0;
  joint.joints.front().b.body = contact::kGround;
  CHECK(message(joint) == "accepted");
  CHECK_THROWS_AS(
      solve_high_precision(spec_of("scenes/free_spin.toml"), {0.0, 1.0}, Precision::kQuad, 1e-31),
      std::invalid_argument);
}

}  // namespace
}  // namespace flexref::precision
