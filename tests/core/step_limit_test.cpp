#include "core/step_limit.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "contact/bushing.hpp"
#include "contact/contact.hpp"
#include "tests/support/contact_models.hpp"
#include "tests/support/flexible_models.hpp"

namespace {

namespace core = flexref::core;
namespace contact = flexref::contact;
namespace testing = flexref::testing;

// Step limits are 2/ω computed from the same doubles along different paths: agreement to a few
// ulps (1e-14 relative) is expected.
constexpr double kRelative = 1e-14;

TEST_CASE("a rigid model without penalty elements has no explicit step limit", "[step_limit]") {
  core::RigidBodyDescription d;
  d.name = "book";
  d.mass = 1.0;
  d.I_Bcm_B = Eigen::Vector3d(1.0, 2.0, 2.8).asDiagonal();
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  const core::Model model(std::move(bodies), {});
  CHECK(core::stiff_modes(model).empty());
  CHECK(!core::explicit_step_limit(model).bounded());
}

TEST_CASE("a flexible body's limit is 2/omega_max of its modes", "[step_limit]") {
  const core::Model model = testing::flexible_spinner_model(core::FlexibleFormulation::kLte, 4);
  const double omega_max = model.body(0).natural_frequencies().maxCoeff();
  const core::StepLimit limit = core::explicit_step_limit(model);
  CHECK(limit.h == Approx(2.0 / omega_max).epsilon(kRelative));
  CHECK(limit.frequency == omega_max);
  CHECK(limit.what == "flexible body spinner");
  const std::vector<core::PenaltyMode> modes = core::stiff_modes(model);
  REQUIRE(modes.size() == 1);
  // ω² = k/m of the highest mode.
  CHECK(modes[0].stiffness / modes[0].inertia == Approx(omega_max * omega_max).epsilon(1e-12));
}

TEST_CASE("a contact's limit is 2/omega at its impact stiffness, the smallest limit wins",
          "[step_limit]") {
  // bouncing_ball: Hunt-Crossley k = 1e6 N/m^1.5, n = 1.5, linearized at the penetration of an
  // impact at v_ref = 4.2 m/s, m_eff = m = 1 kg (tests/support/contact_models.hpp).
  const testing::ContactScene ball = testing::bouncing_ball();
  const std::vector<core::PenaltyMode> modes = core::penalty_modes(ball.model);
  REQUIRE(modes.size() == 1);
  CHECK(modes[0].label == "contact[1]");
  CHECK(modes[0].kind == "contact");
  CHECK(modes[0].inertia == 1.0);
  const double expected = testing::contact_detail::explicit_limit(
      testing::contact_detail::hc_impact_stiffness(1e6, 1.5, 1.0, 4.2), 1.0);
  CHECK(modes[0].step_limit == Approx(expected).epsilon(1e-12));
  CHECK(core::explicit_step_limit(ball.model).h == modes[0].step_limit);
  CHECK(core::explicit_step_limit(ball.model).what == "contact[1]");
}

TEST_CASE("joints give translational and angular modes, numbered per kind", "[step_limit]") {
  const testing::ContactScene scene = testing::pendulum_on_sliding_support();
  const std::vector<core::PenaltyMode> modes = core::penalty_modes(scene.model);
  REQUIRE(modes.size() == 3);
  CHECK(modes[0].label == "joint[1] translational");
  CHECK(modes[1].label == "joint[1] angular");
  CHECK(modes[2].label == "contact[1]");
  double smallest = modes[0].step_limit;
  for (const core::PenaltyMode& m : modes) smallest = std::min(smallest, m.step_limit);
  CHECK(core::explicit_step_limit(scene.model).h == smallest);
}

TEST_CASE("a contact without an effective mass uses its body's mass over its pairs",
          "[step_limit]") {
  core::RigidBodyDescription d;
  d.name = "block";
  d.mass = 2.0;
  d.I_Bcm_B = Eigen::Matrix3d::Identity();
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  std::vector<contact::ContactPair> pairs;
  for (double x : {-0.1, 0.1}) {
    pairs.push_back(contact::ContactPair::point_plane(
        0, Eigen::Vector3d(x, 0.0, 0.0), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()));
  }
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::move(pairs), contact::NormalLaw::linear(4e4, 0.0), contact::FrictionLaw{0.0, 1e-3},
      0.0));
  const core::Model model(std::move(bodies), std::move(elements));
  const std::vector<core::PenaltyMode> modes = core::penalty_modes(model);
  REQUIRE(modes.size() == 1);
  CHECK(modes[0].inertia == 1.0);                                                 // 2 kg / 2 pairs
  CHECK(modes[0].step_limit == Approx(2.0 / std::sqrt(4e4)).epsilon(kRelative));  // ω = 200
}

}  // namespace
