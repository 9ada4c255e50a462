/// A gap support on a worn hole (contact/gap_support.hpp, "Wear"): the force is −∇V of the
/// worn geometry's penalty potential, the sectors' wear rates conserve the worn volume, the
/// power the recession takes out of the spring is −∂V/∂h·ḣ, the law's damping sees the worn
/// surfaces' approach, and a frozen geometry ignores the state's depths.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "contact/gap_support.hpp"

namespace flexref::contact {
namespace {

/// One rigid body whose point N (its frame origin) sits at p_WN in a circular support around the
/// x axis with clearance 1 mm, moving at v_WN.
struct WornHole {
  core::BodyState state;
  std::array<core::BodyKinematics, 1> kinematics;
  std::vector<double> depth;

  WornHole(const Eigen::Vector3d& p_WN, const Eigen::Vector3d& v_WN, unsigned seed) {
    state.p_WBr = p_WN;
    state.v_WBr = v_WN;
    kinematics[0].state = &state;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 2e-4);
    depth.resize(12);
    for (double& h : depth) h = u(rng);
  }
  std::span<const core::BodyKinematics> span() const { return kinematics; }
  core::LoadContext context() const { return {0.0, 0.0, depth}; }
};

core::WearLaw work_rate_law(bool frozen = false, std::vector<double> initial = {}) {
  core::WearLaw law;
  law.kind = core::WearLaw::Kind::kWorkRate;
  law.coefficient = 3e-9;  // 1/Pa, with acceleration 1: rates of ~1e-6 m/s at ~100 N
  law.sectors = 12;
  law.thickness = 0.01;
  law.radius = 0.0105;
  law.geometry_frozen = frozen;
  law.initial_depth = std::move(initial);
  return law;
}

GapSupport worn_support(double damping, double mu, std::optional<core::WearLaw> law) {
  GapSupportGeometry g;
  g.kind = GapSupportGeometry::Kind::kCircular;
  g.a_W = Eigen::Vector3d::UnitX();
  g.clearance = 1e-3;
  return GapSupport(0, Eigen::Vector3d::Zero(), core::NodeAttachment{}, g,
                    NormalLaw::linear(1e6, damping), FrictionLaw{mu, 1e-3}, 1.0, "support",
                    std::move(law));
}

/// A point pressed into the hole at angle φ (from e1 = y toward e2 = z, the x axis) by 0.3 mm
/// beyond its worn clearance there.
Eigen::Vector3d pressed_point(double phi, const std::vector<double>& depth) {
  const WornProfileWeightsTpl<double> w = worn_profile_weights<double>(phi, 12);
  const double h = worn_profile_at<double>(w, depth)[0];
  return (1e-3 + h + 3e-4) * Eigen::Vector3d(0.2, std::cos(phi), std::sin(phi)).normalized();
}

}  // namespace

TEST_CASE("worn gap support: the normal force is -grad V of the worn hole's potential") {
  const GapSupport support = worn_support(0.0, 0.0, work_rate_law());
  for (const double phi : {0.05, 0.7, 1.9, 3.3, 5.9}) {
    WornHole hole(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 5u);
    hole.state.p_WBr = pressed_point(phi, hole.depth);
    // At rest, undamped and frictionless: the force is the spring's alone.
    std::array<core::Wrench, 1> w;
    support.add_wrenches(hole.context(), hole.span(), w);
    for (int k = 0; k < 3; ++k) {
      // V = ½ k δ² ~ 0.1 J, F ~ 300 N; central differences with δp = 1e-9 m have a truncation
      // error δp² |V'''|/6 (V''' ~ k |∇²δ| ~ 1e6/1e-3 N/m²: 2e-16 N) and a round-off
      // ε V/δp ≈ 2e-8 N: 1e-6 relative is far above both and far below a sign or a missing
      // tangential term (h'/|d| ~ 0.1 of the force).
      const double dp = 1e-9;
      WornHole plus = hole, minus = hole;
      plus.kinematics[0].state = &plus.state;
      minus.kinematics[0].state = &minus.state;
      plus.state.p_WBr(k) += dp;
      minus.state.p_WBr(k) -= dp;
      const double fd = -(support.potential_energy(plus.context(), plus.span()) -
                          support.potential_energy(minus.context(), minus.span())) /
                        (2.0 * dp);
      INFO("phi " << phi << ", component " << k);
      CHECK(w[0].f_W(k) == Approx(fd).margin(1e-6 * w[0].f_W.norm()));
    }
    // The worn hole's force is not radial where the profile slopes.
    const Eigen::Vector3d radial = Eigen::Vector3d(0.0, hole.state.p_WBr.y(), hole.state.p_WBr.z());
    CHECK(w[0].f_W.normalized().dot(-radial.normalized()) < 1.0 - 1e-6);
  }
}

TEST_CASE("worn gap support: the sectors' wear rates conserve the work-rate law's volume") {
  const GapSupport support = worn_support(20.0, 0.3, work_rate_law());
  const core::WearLaw law = work_rate_law();
  for (const double phi : {0.2, 2.5, 4.4}) {
    WornHole hole(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.05, -0.4, 0.3), 9u);
    hole.state.p_WBr = pressed_point(phi, hole.depth);
    std::vector<double> rates(12);
    support.wear_depth_rates(hole.context(), hole.span(), rates);
    std::array<core::WearSample, 1> sample;
    support.wear_samples(hole.context(), hole.span(), sample);
    REQUIRE(sample[0].wear_power > 0.0);
    double volume = 0.0;
    int nonzero = 0;
    for (const double r : rates) {
      CHECK(r >= 0.0);
      volume += law.sector_area() * r;
      nonzero += r > 0.0;
    }
    // V̇ = F K_w |F_t·v_t| (the channel's wear power), spread over the two bracketing sectors
    // (hat weights summing to 1): equal to round-off.
    CHECK(volume == Approx(law.rate_factor() * sample[0].wear_power).epsilon(1e-13));
    CHECK(nonzero <= 2);
  }
}

TEST_CASE("worn gap support: the recession releases -dV/dh h' and the damping sees it") {
  const double c = 200.0;  // N·s/m
  const GapSupport support = worn_support(c, 0.3, work_rate_law());
  for (const double phi : {0.4, 3.0}) {
    WornHole hole(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.02, 0.3, -0.2), 13u);
    hole.state.p_WBr = pressed_point(phi, hole.depth);
    std::vector<double> rates(12);
    support.wear_depth_rates(hole.context(), hole.span(), rates);
    const GapSupport::Evaluation e = support.evaluate(hole.context(), hole.span());
    REQUIRE(e.normal.total > 0.0);
    // ḣ(φ) = −dδ/dt at fixed position when the depths grow at their rates: by a finite step of
    // the depths (δ is linear in them, so the difference is exact to round-off, 1e-9 relative).
    const double dt = 1e-3;
    WornHole later = hole;
    later.kinematics[0].state = &later.state;
    for (std::size_t j = 0; j < 12; ++j) later.depth[j] += dt * rates[j];
    const double gap_now = -support.evaluate(hole.context(), hole.span()).point.gap;
    const double gap_later = -support.evaluate(later.context(), later.span()).point.gap;
    const double recession = -(gap_later - gap_now) / dt;
    CHECK(recession > 0.0);
    CHECK(e.recession == Approx(recession).epsilon(1e-9));
    // The law's damping acts on δ̇ = ∇δ·v − ḣ(φ): F = k δ + c (δ̇_kinematic − ḣ(φ)).
    const double delta = -e.point.gap;
    CHECK(e.normal.total == Approx(1e6 * delta + c * (e.delta_dot - e.recession)).epsilon(1e-12));
    // Dissipated power: F_d δ̇ − F_t·v_t + F_e ḣ(φ), the last the spring energy the recession
    // releases (V = V_law(δ) changes by −F_e ḣ(φ) dt at a fixed position).
    const double expected = e.normal.dissipative() * e.delta_dot - e.f_friction_W.dot(e.v_t_W) +
                            e.normal.elastic * e.recession;
    CHECK(support.dissipated_power(hole.context(), hole.span()) == Approx(expected).epsilon(1e-14));
  }
}

TEST_CASE("worn gap support: a frozen geometry sees its initial depths, not the state's") {
  WornHole hole(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.1, 0.2), 21u);
  const std::vector<double> initial = hole.depth;
  hole.state.p_WBr = pressed_point(1.2, initial);
  const GapSupport frozen = worn_support(50.0, 0.3, work_rate_law(true, initial));
  const GapSupport initial_geometry = worn_support(50.0, 0.3, work_rate_law(true, initial));
  WornHole other = hole;
  other.kinematics[0].state = &other.state;
  for (double& h : other.depth) h *= 3.0;  // the state's depths: ignored
  std::array<core::Wrench, 1> a, b;
  frozen.add_wrenches(other.context(), other.span(), a);
  initial_geometry.add_wrenches(core::LoadContext{}, hole.span(), b);
  CHECK(a[0].f_W == b[0].f_W);
  // A frozen geometry does not recede: no release of spring energy, the damping on ∇δ·v alone.
  const GapSupport::Evaluation e = frozen.evaluate(other.context(), other.span());
  CHECK(e.recession == 0.0);
  CHECK(e.volume_rate > 0.0);
}

TEST_CASE("gap support: a wear law needs a name and a circular support, bad laws are refused") {
  GapSupportGeometry g;
  g.clearance = 1e-3;
  const auto make = [&](std::string name, GapSupportGeometry geometry, core::WearLaw law) {
    return GapSupport(0, Eigen::Vector3d::Zero(), core::NodeAttachment{}, geometry,
                      NormalLaw::linear(1e6, 0.0), FrictionLaw{}, 1.0, std::move(name), law);
  };
  CHECK_NOTHROW(make("s", g, work_rate_law()));
  CHECK_THROWS_WITH(make("", g, work_rate_law()), Catch::Contains("needs a name"));
  GapSupportGeometry planar = g;
  planar.kind = GapSupportGeometry::Kind::kPlanar;
  planar.m_W = Eigen::Vector3d::UnitZ();
  CHECK_THROWS_WITH(make("s", planar, work_rate_law()), Catch::Contains("circular"));
  core::WearLaw bad = work_rate_law();
  bad.sectors = 0;
  CHECK_THROWS_WITH(make("s", g, bad), Catch::Contains("sectors >= 1"));
  bad = work_rate_law();
  bad.coefficient = -1.0;
  CHECK_THROWS_WITH(make("s", g, bad), Catch::Contains("coefficient"));
  bad = work_rate_law();
  bad.initial_depth = std::vector<double>(5, 0.0);
  CHECK_THROWS_WITH(make("s", g, bad), Catch::Contains("initial depths"));
}

}  // namespace flexref::contact
