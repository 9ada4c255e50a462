/// Generalized-α on ideal joints beyond the benchmarks' smooth motion (docs/joints.md, "What a
/// jointed solution promises"): its multipliers stay with their rows through a re-selection of
/// the independent rows in motion (the four-bar started on rows that become ill-conditioned at
/// t ≈ 0.22 s), the invariant monitor does not
/// take a joint's reactions or a drive's work for an instability, and a dead point is named.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/invariants.hpp"
#include "core/output_times.hpp"
#include "lie/genalpha.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/run_scheme.hpp"
#include "reference/solve_reference.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/mechanism_scene_texts.hpp"
#include "tests/support/solver_options.hpp"

namespace flexref::lie {
namespace {

// genalpha (ρ∞ = 0.9) over the scene's output grid at step h.
core::Trajectory genalpha_run(const core::Model& model, const scene::Scene& scene, double h,
                              GenAlphaStepper* stepper_out = nullptr) {
  GenAlphaStepper local(model, GenAlphaParameters::from_rho_inf(0.9));
  GenAlphaStepper& stepper = stepper_out != nullptr ? *stepper_out : local;
  return run_scheme(model, stepper, h, core::output_times(scene.end_time, scene.output_step));
}

// The largest distance between the bodies' reference points of two trajectories on one grid.
double genalpha_position_gap(const core::Trajectory& a, const core::Trajectory& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < a.states.size(); ++k) {
    for (std::size_t i = 0; i < a.states[k].size(); ++i) {
      worst = std::max(worst, (a.states[k][i].p_WBr - b.states[k][i].p_WBr).norm());
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("genalpha: multipliers stay with their rows through the four-bar's re-selection",
          "[lie][joints]") {
  // The four-bar's 20 rows have rank 17: three of its 12 out-of-plane rows repeat the others.
  // Started with the tilt rows of A, B and C (3, 8, 13) set aside, the rows kept become
  // ill-conditioned as the loop turns (their pivot ratio falls 100-fold by t ≈ 0.22 s, while all
  // rows keep their rank): the stepper's tracker chooses them again and carries λ̂ over as the
  // same reactions. IDA, started on the same rows, switches its DAE's rows at a root.
  const scene::Scene scene = scene::read_scene("scenes/four_bar.toml");
  std::vector<int> rows;
  for (int r = 0; r < 20; ++r) {
    if (r != 3 && r != 8 && r != 13) rows.push_back(r);
  }
  const core::Model model =
      scene::build_model(scene.spec, core::FlexibleFormulation::kCoupled, rows);
  REQUIRE(model.independent_rows() == rows);
  const double h = 1e-3;
  GenAlphaStepper stepper(model, GenAlphaParameters::from_rho_inf(0.9));
  const core::Trajectory run = genalpha_run(model, scene, h, &stepper);
  CHECK(stepper.multiplier_rows() != rows);
  const reference::ReferenceRun reference = reference::solve_reference(
      "cvode", model, core::output_times(scene.end_time, scene.output_step),
      testing::with_rtol(1e-10));
  const double gap = genalpha_position_gap(run, reference.trajectory);
  INFO("largest position gap to CVODE " << gap << " m");
  // IDA through its own switch of rows: both at rtol 1e-10 on a motion of 0.4 m, they agree to
  // ~1e-9 m; 1e-7 leaves a hundredfold margin and catches multipliers on the wrong rows, which
  // fail the corrector or leave the joints by far more.
  const reference::ReferenceRun ida = reference::solve_reference(
      "ida", model, core::output_times(scene.end_time, scene.output_step),
      testing::with_rtol(1e-10));
  CHECK(genalpha_position_gap(ida.trajectory, reference.trajectory) < 1e-7);
  // Second order: the error at h = 1e-3 is C h² with C the motion's third derivatives over the
  // horizon (crank at 10 to 23 rad/s, links of 0.1–0.4 m: C ≲ 0.4 m × 23² rad²/s² × 2 s ≈ 400):
  // 4e-4 m bounds it; rows paired with the wrong multipliers fail Newton or leave the joints.
  CHECK(gap < 4e-4);
  // At the last output the multipliers, on the rows they belong to, give the reactions the
  // index-1 solve gives there (one generalized force whatever the basis of the rows' span).
  core::Workspace ws = model.make_workspace();
  core::Accelerations acc = model.make_accelerations();
  const double t = stepper.time();
  model.compute_accelerations({t, t}, stepper.state(), ws, acc);
  const Eigen::VectorXd lambda = stepper.multipliers();
  const core::JointMultipliers solved = model.joint_multipliers(ws);
  Eigen::VectorXd force = Eigen::VectorXd::Zero(solved.force().size());
  for (std::size_t i = 0; i < stepper.multiplier_rows().size(); ++i) {
    force -= lambda(static_cast<Eigen::Index>(i)) *
             solved.J().row(stepper.multiplier_rows()[i]).transpose();
  }
  const double scale = solved.force().cwiseAbs().maxCoeff();
  INFO("generalized reactions " << scale << ", difference "
                                << (force - solved.force()).cwiseAbs().maxCoeff());
  // genalpha's λ_n is the scheme's, second-order accurate: h² × the reactions' second time
  // derivative (~Ω² at 23 rad/s: 5e2) relative, 5e-4, ×10 for the scheme's constant.
  CHECK((force - solved.force()).cwiseAbs().maxCoeff() < 5e-3 * scale);
}

TEST_CASE("genalpha: joints to the ground and drives are not instabilities", "[lie][joints]") {
  SECTION("the driven slider-crank: momentum not monitored, the balance with W_drive kept") {
    const scene::Scene scene = scene::read_scene("scenes/slider_crank.toml");
    const core::Trajectory run = genalpha_run(*scene.model, scene, 1e-4);
    const core::InvariantCheck check = core::check_invariants(*scene.model, run);
    INFO("worst relative change " << check.worst_relative << " of " << check.worst_quantity);
    CHECK_FALSE(check.invariants.momentum());
    CHECK(check.invariants.energy());
    CHECK_FALSE(check.breach.has_value());
    // The energy balance's error is the scheme's: second order, h² Ω² ~ 2e-4 of the swing.
    CHECK(check.worst_relative < 1e-2);
  }
  SECTION("a slider driven along its guide") {
    // The slider-crank pushed from the crank at π/2 towards its bottom dead centre, stopped at
    // 0.15 s, 0.07 s before it: the drive's work is the mechanism's kinetic energy.
    const scene::Scene scene = scene::parse_scene(
        testing::driven_slider_scene_text(std::numbers::pi / 2, -0.5, 0.15), "push.toml");
    const core::Trajectory run = genalpha_run(*scene.model, scene, 1e-4);
    const core::InvariantCheck check = core::check_invariants(*scene.model, run);
    INFO("worst relative change " << check.worst_relative << " of " << check.worst_quantity);
    CHECK(check.invariants.energy());
    CHECK_FALSE(check.breach.has_value());
  }
}

TEST_CASE("genalpha: Newton follows its residual down through a tip's frictional impact",
          "[lie][joints]") {
  // The ideal double pendulum's tip strikes the floor at t = 0.558 s (Hunt–Crossley, tanh
  // friction regularized at 1e-3 m/s). Without the line search Newton cycled at a relative
  // residual of 0.017 for 30 iterations at t = 0.56 s at h = 1e-4 (and 0.0084 at 5e-5): the
  // friction's slope holds over less than a full correction. Through the impact and its release.
  scene::Scene scene = scene::read_scene("scenes/double_pendulum_ideal_strike.toml");
  scene.end_time = 0.6;
  for (const double h : {1e-4, 5e-5}) {
    INFO("h = " << h);
    GenAlphaStepper stepper(*scene.model, GenAlphaParameters::from_rho_inf(0.9));
    stepper.initialize(0.0, scene.model->initial_state());
    const long steps = std::lround(scene.end_time / h);
    std::string failure;
    for (long n = 0; n < steps && failure.empty(); ++n) failure = stepper.step(h).message;
    INFO(failure);
    CHECK(failure.empty());
    // The contact's clamp and the friction's tanh are not smooth: up to ~20 iterations where a
    // step crosses them (17 measured at t = 0.56 s), never the budget's 30.
    CHECK(stepper.max_newton_iterations() < GenAlphaStepper::kMaxNewtonIterations);
  }
}

TEST_CASE("genalpha: a dead point passed in motion is named, not a Newton failure",
          "[lie][joints]") {
  // The parallelogram four-bar driven into its change point at t = π/2.
  const scene::Scene scene =
      scene::parse_scene(testing::parallelogram_scene_text(2.0), "parallelogram.toml");
  std::string message;
  try {
    (void)genalpha_run(*scene.model, scene, 1e-3);
  } catch (const core::SolverError& e) {
    message = e.what();
  }
  INFO("message: " << message);
  REQUIRE(!message.empty());
  CHECK_THAT(message, Catch::Matchers::Contains("singular configuration"));
  CHECK_THAT(message, Catch::Matchers::Contains("joint '"));
}

}  // namespace flexref::lie
