/// Point and sphere contacts with a wear law (contact/contact.hpp, "Wear"): each pair's worn depth
/// widens its gap, its Archard rate is F k F_n |v_t| / (H A), its damping sees the worn
/// surfaces' approach, and the model refuses a state without its depths.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "contact/contact.hpp"
#include "core/model.hpp"

namespace flexref::contact {
namespace {

core::WearLaw archard_law() {
  core::WearLaw law;
  law.kind = core::WearLaw::Kind::kArchard;
  law.coefficient = 1e-4;
  law.hardness = 1e9;
  law.area = 1e-6;
  law.acceleration = 4000.0;
  return law;
}

/// A body whose frame origin slides at v over the plane z = 0, two pins below it.
struct SlidingPins {
  core::BodyState state;
  std::array<core::BodyKinematics, 1> kinematics;
  std::vector<double> depth{3e-5, 1e-5};

  SlidingPins() {
    state.p_WBr = Eigen::Vector3d(0.0, 0.0, 0.05 - 5e-5);  // pins at z = −5e-5
    state.v_WBr = Eigen::Vector3d(0.8, -0.3, -2e-3);
    kinematics[0].state = &state;
  }
  std::span<const core::BodyKinematics> span() const { return kinematics; }
  core::LoadContext context() const { return {0.0, 0.0, depth}; }
};

ContactElement pins(double damping, std::optional<core::WearLaw> law) {
  std::vector<ContactPair> p{
      ContactPair::point_plane(0, Eigen::Vector3d(0.05, 0.0, -0.05), Eigen::Vector3d::Zero(),
                               Eigen::Vector3d::UnitZ()),
      ContactPair::point_plane(0, Eigen::Vector3d(-0.05, 0.0, -0.05), Eigen::Vector3d::Zero(),
                               Eigen::Vector3d::UnitZ())};
  return ContactElement(std::move(p), NormalLaw::linear(1e5, damping), FrictionLaw{0.2, 1e-3}, 0.25,
                        "pins", std::move(law));
}

}  // namespace

TEST_CASE("worn pins: the depth widens the gap, and the Archard rate is F k F_n |v_t| / (H A)") {
  const double c = 30.0;
  const ContactElement worn = pins(c, archard_law());
  const ContactElement plain = pins(c, std::nullopt);
  SlidingPins b;
  std::array<double, 2> g_worn{}, g_plain{};
  worn.switching_functions(b.context(), b.span(), g_worn);
  plain.switching_functions(core::LoadContext{}, b.span(), g_plain);
  std::array<double, 2> rates{};
  worn.wear_depth_rates(b.context(), b.span(), rates);
  const core::WearLaw law = archard_law();
  for (int i = 0; i < 2; ++i) {
    const auto k = static_cast<std::size_t>(i);
    // g + h: the pin's tip is worn back along the normal.
    CHECK(g_worn[k] == Approx(g_plain[k] + b.depth[k]).margin(1e-18));
    const ContactEvaluation e = worn.evaluate(b.context(), i, b.span());
    REQUIRE(e.normal.total > 0.0);
    const double slip = e.v_t_W.norm();
    CHECK(slip == Approx(std::hypot(0.8, 0.3)).epsilon(1e-12));
    // ḣ = F k F_n |v_t| / (H A): 4000·1e-4/(1e9·1e-6) = 4e-4 m/(N·m) per F_n |v_t|.
    CHECK(rates[k] == Approx(4e-4 * e.normal.total * slip).epsilon(1e-14));
    CHECK(e.recession == Approx(rates[k]).epsilon(1e-14));
    // The damping sees δ̇ = −n·v − ḣ: F = k δ + c (2e-3 − ḣ), the tip receding at ḣ.
    const double delta = -(g_plain[k] + b.depth[k]);
    CHECK(e.normal.total == Approx(1e5 * delta + c * (2e-3 - rates[k])).epsilon(1e-13));
    // The spring's potential is that of the worn penetration.
    CHECK(e.normal.elastic == Approx(1e5 * delta).epsilon(1e-14));
  }
  // The potential of the worn pins, ½ k Σ δ_i².
  double v = 0.0;
  for (int i = 0; i < 2; ++i) {
    const double delta =
        -(g_plain[static_cast<std::size_t>(i)] + b.depth[static_cast<std::size_t>(i)]);
    v += 0.5e5 * delta * delta;
  }
  CHECK(worn.potential_energy(b.context(), b.span()) == Approx(v).epsilon(1e-14));
}

TEST_CASE("worn pins: a pin worn through its penetration no longer touches") {
  const ContactElement worn = pins(30.0, archard_law());
  SlidingPins b;
  b.depth = {6e-5, 6e-5};  // deeper than the 5e-5 m the pins reach below the plane
  std::array<core::Wrench, 1> w;
  w[0].set_zero();
  worn.add_wrenches(b.context(), b.span(), w);
  CHECK(w[0].f_W.isZero(0.0));
  std::array<double, 2> rates{1.0, 1.0};
  worn.wear_depth_rates(b.context(), b.span(), rates);
  CHECK(rates[0] == 0.0);
  CHECK(rates[1] == 0.0);
}

TEST_CASE("worn spheres: sphere-plane and sphere-sphere gaps widen by the depth") {
  // Body 0 slides over the plane z = 0 with a 2 cm sphere 1e-4 m into it; body 1 carries a
  // 3 cm sphere 5e-5 m into body 0's second sphere; work-rate wear on both pairs.
  core::BodyState s0, s1;
  s0.p_WBr = Eigen::Vector3d(0.0, 0.0, 0.02 - 1e-4);
  s0.v_WBr = Eigen::Vector3d(0.5, 0.0, 0.0);
  s1.p_WBr = Eigen::Vector3d(0.0, 0.0, 0.02 - 1e-4 + 0.5 + 0.05 - 5e-5);
  s1.v_WBr = Eigen::Vector3d(-0.2, 0.1, 0.0);
  std::array<core::BodyKinematics, 2> k;
  k[0].state = &s0;
  k[1].state = &s1;
  const std::span<const core::BodyKinematics> bodies(k);
  const auto spheres = [](std::optional<core::WearLaw> law) {
    std::vector<ContactPair> p{
        ContactPair::sphere_plane(0, Eigen::Vector3d::Zero(), 0.02, Eigen::Vector3d::Zero(),
                                  Eigen::Vector3d::UnitZ()),
        ContactPair::sphere_sphere(0, Eigen::Vector3d(0.0, 0.0, 0.5), 0.02, 1,
                                   Eigen::Vector3d::Zero(), 0.03)};
    return ContactElement(std::move(p), NormalLaw::linear(1e5, 0.0), FrictionLaw{0.3, 1e-3}, 0.25,
                          "balls", std::move(law));
  };
  core::WearLaw law;
  law.kind = core::WearLaw::Kind::kWorkRate;
  law.coefficient = 2e-14;
  law.area = 1e-6;
  law.acceleration = 1e4;
  const ContactElement worn = spheres(law);
  const ContactElement plain = spheres(std::nullopt);
  const std::vector<double> depth{3e-5, 2e-5};
  const core::LoadContext context{0.0, 0.0, depth};
  std::array<double, 2> g_worn{}, g_plain{}, rates{};
  worn.switching_functions(context, bodies, g_worn);
  plain.switching_functions(core::LoadContext{}, bodies, g_plain);
  worn.wear_depth_rates(context, bodies, rates);
  for (int i = 0; i < 2; ++i) {
    const auto j = static_cast<std::size_t>(i);
    INFO("pair " << i);
    // g + h: the worn sphere's radius is r − h (the gaps are −1e-4 and −5e-5 m unworn; both
    // are one subtraction from numbers of order 0.5 m, so 1e-15 m covers their round-off).
    CHECK(g_plain[j] == Approx(i == 0 ? -1e-4 : -5e-5).margin(1e-15));
    CHECK(g_worn[j] == Approx(g_plain[j] + depth[j]).margin(1e-15));
    // ḣ = F K_w |F_t · v_t| / A: 1e4 · 2e-14 / 1e-6 = 2e-4 per watt of friction power.
    const ContactEvaluation e = worn.evaluate(context, i, bodies);
    REQUIRE(e.normal.total > 0.0);
    CHECK(rates[j] == Approx(2e-4 * std::abs(e.f_friction_W.dot(e.v_t_W))).epsilon(1e-14));
    CHECK(rates[j] > 0.0);
  }
}

TEST_CASE("a model with a wear law refuses a state without its depths") {
  std::vector<core::Body> bodies;
  core::RigidBodyDescription d;
  d.name = "block";
  d.mass = 1.0;
  d.I_Bcm_B = Eigen::Matrix3d::Identity() * 1e-3;
  bodies.emplace_back(d);
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::make_unique<ContactElement>(pins(30.0, archard_law())));
  const core::Model model(std::move(bodies), std::move(elements));
  REQUIRE(model.wear_depth_count() == 2);
  REQUIRE(model.channel_depth_count(0) == 2);
  CHECK(model.wear_depth_areas() == std::vector<double>{1e-6, 1e-6});
  core::State state = model.initial_state();
  CHECK(state.wear_depth.size() == 2);
  core::Workspace ws = model.make_workspace();
  core::Accelerations acc = model.make_accelerations();
  CHECK_NOTHROW(model.compute_accelerations({0.0, 0.0}, state, ws, acc));
  state.wear_depth.resize(0);
  CHECK_THROWS_WITH(model.compute_accelerations({0.0, 0.0}, state, ws, acc),
                    Catch::Contains("worn depths"));
}

TEST_CASE("a contact with a wear law needs a name and a positive pin area") {
  std::vector<ContactPair> p{ContactPair::point_plane(
      0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ())};
  CHECK_THROWS_WITH(
      ContactElement(p, NormalLaw::linear(1e5, 0.0), FrictionLaw{}, 0.0, "", archard_law()),
      Catch::Contains("needs a name"));
  core::WearLaw law = archard_law();
  law.area = 0.0;
  CHECK_THROWS_WITH(ContactElement(p, NormalLaw::linear(1e5, 0.0), FrictionLaw{}, 0.0, "c", law),
                    Catch::Contains("pin area"));
  law = archard_law();
  law.hardness = 0.0;
  CHECK_THROWS_WITH(ContactElement(p, NormalLaw::linear(1e5, 0.0), FrictionLaw{}, 0.0, "c", law),
                    Catch::Contains("hardness"));
}

}  // namespace flexref::contact
