#include "core/invariants.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/applied_load.hpp"
#include "core/gravity.hpp"
#include "core/time_profile.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A single free body (m = 1, J = diag(j)) with initial angular velocity w0 and the elements.
Model one_body(const Eigen::Vector3d& j, const Eigen::Vector3d& w0, testing::Elements elements,
               MotionKind motion = MotionKind::kFree) {
  RigidBodyDescription d = testing::rigid_body("b", 1.0, j, w0);
  d.motion = motion;
  std::vector<Body> bodies;
  bodies.emplace_back(d);
  return Model(std::move(bodies), std::move(elements));
}

testing::Elements torque(TimeProfile profile) {
  testing::Elements e;
  e.push_back(std::make_unique<AppliedTorque>(0, Eigen::Vector3d(0.2, 0.0, 0.2), LoadFrame::kWorld,
                                              profile));
  return e;
}

TEST_CASE("model_invariants reads what the model conserves from its elements and bodies",
          "[core][invariants]") {
  const Eigen::Vector3d j(3.0, 4.0, 5.0);
  const Eigen::Vector3d w0(0.2, 0.3, 2.0);
  SECTION("a torque-free free body conserves energy and momentum from the start") {
    const ModelInvariants in = model_invariants(testing::free_spin());
    CHECK(in.energy_from == -kInf);
    CHECK(in.momentum_from == -kInf);
  }
  SECTION("a torque pulse: both from the pulse's end on (book_toss: 0.1 s)") {
    const ModelInvariants in = model_invariants(testing::book_toss());
    CHECK(in.energy_from == 0.1);
    CHECK(in.momentum_from == 0.1);
  }
  SECTION("a constant torque keeps doing untracked work and loads the body: neither") {
    const ModelInvariants in = model_invariants(one_body(j, w0, torque(TimeProfile::constant())));
    CHECK_FALSE(in.energy());
    CHECK_FALSE(in.momentum());
    CHECK(in.energy_reason.find("keeps doing work") != std::string::npos);
    CHECK(in.momentum_reason.find("from outside") != std::string::npos);
  }
  SECTION("a harmonic force on a model that dissipates nothing: its work is not tracked") {
    testing::Elements e;
    e.push_back(std::make_unique<AppliedForce>(0, Eigen::Vector3d(1.0, 0.0, 0.0), LoadFrame::kWorld,
                                               Eigen::Vector3d::Zero(),
                                               TimeProfile::harmonic(10.0, 0.0)));
    const Model model = one_body(j, w0, std::move(e));
    REQUIRE_FALSE(model.dissipates());
    CHECK_FALSE(model_invariants(model).energy());
  }
  SECTION("gravity is conservative but an outside load: energy only") {
    const ModelInvariants in = model_invariants(testing::heavy_top());
    CHECK(in.energy_from == -kInf);
    CHECK_FALSE(in.momentum());
    CHECK(in.momentum_reason.find("pivot") != std::string::npos);
  }
  SECTION("an element that does not say is never taken to conserve anything") {
    const ModelInvariants in = model_invariants(testing::damped_coulomb_wall());
    CHECK_FALSE(in.energy());
    CHECK_FALSE(in.momentum());
  }
}

/// The free body's state with the angular velocity replaced.
State with_w(const Model& model, const Eigen::Vector3d& w) {
  State s = model.initial_state();
  s[0].w_WB_B = w;
  return s;
}

TEST_CASE(
    "the invariant monitor flags a change beyond the tolerance with its time and quantity and size",
    "[core][invariants]") {
  const Model model = testing::free_spin();
  const Eigen::Vector3d w0(0.2, 0.3, 2.0);
  SECTION("energy") {
    InvariantMonitor monitor(model);
    CHECK_FALSE(monitor.observe(0.0, with_w(model, w0), 0.0, 0.0));
    // W·√1.05: kinetic energy +5 % (of its scale, the largest kinetic energy, 1.05 E0: 4.8 %).
    CHECK_FALSE(monitor.observe(1.0, with_w(model, std::sqrt(1.05) * w0), 0.0, 0.0));
    // 1e-12: the monitor's sums and ratios of a few O(10 J) numbers round at ~1e-15 relative.
    CHECK(monitor.worst_relative() == Approx(0.05 / 1.05).epsilon(1e-12));
    CHECK(monitor.worst_quantity() == "energy balance");
    // W·√1.5: +50 % = 0.33 of the scale 1.5 E0, above the tolerance 0.25. The angular momentum
    // changes by √1.5 − 1 = 0.22 of |π0|, 0.18 of its scale √1.5 |π0|: below.
    const auto& breach = monitor.observe(2.0, with_w(model, std::sqrt(1.5) * w0), 0.0, 0.0);
    REQUIRE(breach);
    CHECK(breach->quantity == "energy balance");
    CHECK(breach->t == 2.0);
    CHECK(breach->t0 == 0.0);
    const double e0 = model.kinetic_energy(with_w(model, w0));
    // 1e-12: round-off of a few operations, as above.
    CHECK(breach->change == Approx(0.5 * e0).epsilon(1e-12));
    CHECK(breach->relative() == Approx(0.5 / 1.5).epsilon(1e-12));
    const std::string text = breach->describe();
    CHECK(text.find("energy balance") != std::string::npos);
    CHECK(text.find("at t = 2 s") != std::string::npos);
    CHECK(text.find("33.3 %") != std::string::npos);
    // Later states do not replace the first breach.
    CHECK(monitor.observe(3.0, with_w(model, w0), 0.0, 0.0)->t == 2.0);
  }
  SECTION("dissipated work is in the balance") {
    // heavy_top (a pivot: energy only). Half the kinetic energy lost and the same amount
    // dissipated: E + W_d unchanged.
    const Model top = testing::heavy_top();
    const Eigen::Vector3d w = top.initial_state()[0].w_WB_B;
    InvariantMonitor monitor(top);
    const double e0 = top.kinetic_energy(with_w(top, w));
    CHECK_FALSE(monitor.observe(0.0, with_w(top, w), 0.0, 0.0));
    CHECK_FALSE(monitor.observe(1.0, with_w(top, std::sqrt(0.5) * w), 0.5 * e0, 0.0).has_value());
    // Without the dissipated work the same state is a loss of half the energy: a breach.
    InvariantMonitor blind(top);
    blind.observe(0.0, with_w(top, w), 0.0, 0.0);
    CHECK(blind.observe(1.0, with_w(top, std::sqrt(0.5) * w), 0.0, 0.0).has_value());
  }
  SECTION("angular momentum") {
    // A spherical body (J = 2 I): turning W by 30° about an axis normal to it keeps the energy
    // and turns π by 30°, a change of 2 sin(15°) = 0.52 of |π|.
    testing::Elements none;
    const Model sphere = one_body({2.0, 2.0, 2.0}, w0, std::move(none));
    InvariantMonitor monitor(sphere);
    CHECK_FALSE(monitor.observe(0.0, with_w(sphere, w0), 0.0, 0.0));
    const Eigen::Vector3d axis = w0.cross(Eigen::Vector3d::UnitX()).normalized();
    const Eigen::Vector3d turned = Eigen::AngleAxisd(std::numbers::pi / 6.0, axis) * w0;
    const auto& breach = monitor.observe(0.5, with_w(sphere, turned), 0.0, 0.0);
    REQUIRE(breach);
    CHECK(breach->quantity == "angular momentum");
    // 1e-12: round-off of the rotation and the norms, ~1e-15.
    CHECK(breach->relative() == Approx(2.0 * std::sin(std::numbers::pi / 12.0)).epsilon(1e-12));
  }
  SECTION("nothing is monitored before the model conserves it (book_toss's pulse)") {
    const Model book = testing::book_toss();
    InvariantMonitor monitor(book);
    const Eigen::Vector3d w(0.0, 10.0, 0.0);
    // During the pulse the torque may change the energy by any amount.
    CHECK_FALSE(monitor.observe(0.0, with_w(book, w), 0.0, 0.0));
    CHECK_FALSE(monitor.observe(0.05, with_w(book, 3.0 * w), 0.0, 0.0));
    // From 0.1 on it is measured from the first monitored output.
    CHECK_FALSE(monitor.observe(0.1, with_w(book, w), 0.0, 0.0));
    const auto& breach = monitor.observe(0.2, with_w(book, 2.0 * w), 0.0, 0.0);
    REQUIRE(breach);
    CHECK(breach->t0 == 0.1);
  }
}

}  // namespace
}  // namespace flexref::core
