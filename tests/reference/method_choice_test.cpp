/// \file method_choice_test.cpp
/// CVODE's method choice (reference/method_choice.hpp): Adams without a stiff element, BDF for
/// contacts and for heavily damped fast modes, the reason recorded in the run, and the override.
#include "reference/method_choice.hpp"

#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "contact/bushing.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/reference_solver.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/contact_models.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

/// A rod (m = 1, L = 1, hinge at its frame origin, J_C = diag(1e-3, 1/12, 1/12)) hanging
/// straight down at rest from a spherical bushing (k = 1e6 N/m) with damping c: the bushing's
/// translational modes have ω = √(k/m_eff) ≈ 1e3–2e3 rad/s, damping ratio ζ = c/(2√(k m_eff)).
core::Model rod_on_bushing(double damping) {
  core::RigidBodyDescription d;
  d.name = "rod";
  d.mass = 1.0;
  d.p_BoBcm_B = Eigen::Vector3d(0.5, 0.0, 0.0);
  d.I_Bcm_B = Eigen::Vector3d(1e-3, 1.0 / 12.0, 1.0 / 12.0).asDiagonal();
  // x axis down: 90° about y.
  d.initial.theta_WB = rotation::EulerParameters(std::sqrt(0.5), 0.0, std::sqrt(0.5), 0.0);
  contact::BushingParameters p;
  p.stiffness = 1e6;
  p.damping = damping;
  testing::Elements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0.0, 0.0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, 1.0, Eigen::Vector3d(0.5, 0.0, 0.0)}}));
  elements.push_back(std::make_unique<contact::SphericalBushing>(
      contact::BushingEnd{0, Eigen::Vector3d::Zero()},
      contact::BushingEnd{contact::kGround, Eigen::Vector3d::Zero()}, p));
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  return core::Model(std::move(bodies), std::move(elements));
}

}  // namespace

TEST_CASE("CVODE's method: Adams unless contact or a heavily damped fast mode", "[cvode][method]") {
  SECTION("rigid scenes without contact: Adams") {
    for (const core::Model& model : {testing::free_spin(), testing::heavy_top(),
                                     testing::coulomb_wall(), testing::book_toss()}) {
      const CvodeMethodChoice choice = choose_cvode_method(model);
      CAPTURE(choice.reason);
      CHECK(choice.method == CvodeMethod::kAdams);
      CHECK(choice.reason.find("non-stiff") == 0);
    }
  }
  SECTION("flexible bodies with undamped modes: Adams (the modes are resolved anyway)") {
    // Fastest rate 40 rad/s, no decay (measured: Adams 2.3e3 steps against BDF 7.1e3 at rtol
    // 1e-12 on the scene, 4× more accurate).
    const CvodeMethodChoice choice =
        choose_cvode_method(testing::flexible_spinner_model(core::FlexibleFormulation::kCoupled));
    CAPTURE(choice.reason);
    CHECK(choice.method == CvodeMethod::kAdams);
  }
  SECTION("a contact: BDF") {
    const CvodeMethodChoice choice = choose_cvode_method(testing::bouncing_ball().model);
    CAPTURE(choice.reason);
    CHECK(choice.method == CvodeMethod::kBdf);
    CHECK(choice.reason.find("contact") != std::string::npos);
  }
  SECTION("a stiff joint: BDF when heavily damped, Adams when lightly damped") {
    // c = 1e5 N·s/m: ζ ≈ 1e5/(2√(1e6 · 1)) = 50, overdamped; the fast real eigenvalue
    // ≈ −c/m_eff ≈ −1e5/s, far above 10× the rod's resolved rates (the bushing's slow real
    // mode k/c = 10/s and the swing ≈ 3 rad/s). c = 0: the joint modes are eigenvalues
    // ±i·1e3, resolved by any accurate method, so Adams.
    const StiffnessSummary damped = summarize_stiffness(rod_on_bushing(1e5));
    CAPTURE(damped.fastest_decay, damped.resolved_rate, damped.fastest_rate);
    CHECK(damped.stiff());
    CHECK(choose_cvode_method(rod_on_bushing(1e5)).method == CvodeMethod::kBdf);
    const StiffnessSummary undamped = summarize_stiffness(rod_on_bushing(0.0));
    CAPTURE(undamped.fastest_decay, undamped.resolved_rate, undamped.fastest_rate);
    CHECK(!undamped.stiff());
    CHECK(undamped.fastest_rate > 500.0);  // the joint is there, and fast
    CHECK(choose_cvode_method(rod_on_bushing(0.0)).method == CvodeMethod::kAdams);
  }
}

TEST_CASE("the rotation is weighted per unit step where it sets the steps", "[method]") {
  // reference/error_weights.hpp: smooth, non-stiff models (CVODE's Adams), not contact or
  // stiffness; IDA also leaves out ideal joints (ida_solver.cpp).
  for (const core::Model& model : {testing::free_spin(), testing::heavy_top(),
                                   testing::coulomb_wall(), testing::book_toss()}) {
    CHECK(rotation_weights_per_step(summarize_stiffness(model, 0.01)));
  }
  const scene::Scene jointed = scene::read_scene("scenes/heavy_top_spherical.toml");
  CHECK(rotation_weights_per_step(summarize_stiffness(*jointed.model, 0.01)));
  CHECK(rotation_weights_per_step(summarize_stiffness(
      testing::flexible_spinner_model(core::FlexibleFormulation::kCoupled), 0.01)));
  const testing::ContactScene ball = testing::bouncing_ball();
  CHECK(!rotation_weights_per_step(summarize_stiffness(ball.model, 0.01)));
  CHECK(!rotation_weights_per_step(summarize_stiffness(rod_on_bushing(1e5), 0.01)));
}

TEST_CASE("solve_cvode records its method and why, --method overrides", "[cvode][method]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(1.0, 0.5);
  SolverOptions options;
  const ReferenceRun automatic = solve_cvode(model, times, options);
  CHECK(automatic.method == "adams");
  CHECK(automatic.method_reason.find("non-stiff") == 0);
  options.cvode_method = CvodeMethod::kBdf;
  const ReferenceRun bdf = solve_cvode(model, times, options);
  CHECK(bdf.method == "bdf");
  CHECK(bdf.method_reason == "chosen with --method");
  // Different methods, different steps (BDF takes more on this smooth scene).
  CHECK(bdf.stats.steps != automatic.stats.steps);
}

TEST_CASE("CVODE method names", "[cvode][method]") {
  for (CvodeMethod m : {CvodeMethod::kAuto, CvodeMethod::kAdams, CvodeMethod::kBdf}) {
    CHECK(parse_cvode_method(to_string(m)) == m);
  }
  CHECK_THROWS_AS(parse_cvode_method("rk4"), std::invalid_argument);
}

}  // namespace flexref::reference
