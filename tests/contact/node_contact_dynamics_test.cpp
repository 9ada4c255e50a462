/// Contacts at deforming points in motion, integrated by the references:
///  - rigid limit: a flexible body whose only node carries the contact and whose modes are very
///    stiff (and critically damped) reproduces the rigid body's bouncing ball and sliding block;
///  - friction work: the sliding block's wear work is μ m g cos α × the sliding distance;
///  - a modal oscillator hitting a stop: the onset time π/6 located by every reference, the
///    impact count, and the restitution of the Hunt–Crossley law.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "contact/contact.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "reference/reference_solver.hpp"
#include "tests/support/node_contact_models.hpp"

namespace flexref {
namespace {

using Elements = std::vector<std::unique_ptr<const core::ForceElement>>;

constexpr double kG = 9.81;

/// A rigid particle (m, contact at its centre, K = 0) or the stiff flexible particle of the
/// same total mass (hub m/2 + node m/2, modal stiffness K > 0, ζ = 1), with gravity and one
/// contact pair against the plane (Q, n), sphere radius r, at the centre or the node.
core::Model particle(double K, double m, double r, const Eigen::Vector3d& p0,
                     const Eigen::Vector3d& v0, const Eigen::Vector3d& p_WQ,
                     const Eigen::Vector3d& n_W, const contact::NormalLaw& law,
                     contact::FrictionLaw friction) {
  core::RigidBodyDescription d;
  const bool flexible = K > 0.0;
  if (flexible) {
    d = testing::stiff_particle_body("particle", 0.5 * m, 0.01, 0.5 * m, K);
    d.flexible->modal.damping_ratio.setConstant(1.0);
  } else {
    d.name = "particle";
    d.mass = m;
    d.I_Bcm_B = Eigen::Matrix3d::Identity() * 0.01;
  }
  d.initial.p_WBo = p0;
  d.initial.v_WBo = v0;
  contact::ContactPair pair =
      contact::ContactPair::sphere_plane(0, Eigen::Vector3d::Zero(), r, p_WQ, n_W);
  if (flexible) pair.node_b = testing::node_of(d, 0);
  Elements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0.0, 0.0, -kG),
      std::vector<core::UniformGravity::BodyMass>{{0, m, Eigen::Vector3d::Zero()}}));
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{pair}, law, friction, 0.5 * m, "contact"));
  std::vector<core::Body> bodies;
  bodies.emplace_back(d);
  return core::Model(std::move(bodies), std::move(elements));
}

std::vector<double> grid(double end, double step) {
  std::vector<double> t;
  for (int k = 0; k * step <= end + 1e-12; ++k) t.push_back(k * step);
  return t;
}

/// The contact point's world position: the rigid particle's centre or the flexible node.
Eigen::Vector3d centre(const core::Model& m, const core::State& s) {
  return m.p_WP(0, s[0],
                m.body(0).description().points.empty()
                    ? core::TrackedPoint{"c", Eigen::Vector3d::Zero(), -1}
                    : m.body(0).description().points.front());
}

TEST_CASE("rigid limit: a stiff flexible body bouncing on its node is the rigid bouncing ball") {
  const auto law = contact::NormalLaw::hunt_crossley(1e7, 1.5, 0.8, 3.0);
  const auto build = [&](double K) {
    return particle(K, 2.0, 0.1, Eigen::Vector3d(0.0, 0.0, 0.5), Eigen::Vector3d(0.3, 0.0, 0.0),
                    Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), law, contact::FrictionLaw{});
  };
  const core::Model rigid = build(0.0);
  reference::SolverOptions o;
  o.rtol = 1e-9;
  const std::vector<double> t = grid(1.2, 0.01);
  const reference::ReferenceRun a = reference::solve_cvode(rigid, t, o);
  // Impacts at 0.29, 0.74 and 1.11 s (0.4 m drop at 2.8 m/s, then flights of 2·0.8ⁿ·2.8/g).
  CHECK(a.trajectory.impacts.back() == 3.0);
  std::vector<double> distance;
  for (const double K : {1e9, 1e11}) {
    const core::Model flexible = build(K);
    const reference::ReferenceRun b = reference::solve_cvode(flexible, t, o);
    double worst = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      worst = std::max(
          worst, (centre(rigid, a.trajectory.states[k]) - centre(flexible, b.trajectory.states[k]))
                     .norm());
    }
    distance.push_back(worst);
    CHECK(b.trajectory.impacts.back() == a.trajectory.impacts.back());
  }
  // The flexible particle differs from the rigid one by its internal mode: during the ~2 ms
  // contact (peak force ~4e3 N) the node moves relative to the hub by F/K with rate
  // Ḟ/K ~ 4e-3·(1e9/K) m/s, and the critical damper c = 2√(K m_node) dissipates
  // c (Ḟ/K)² τ ∝ K^{-3/2} — 2e-3 J of 8.8 J at K = 1e9 (measured distance 1.4e-4 m after the
  // bounces). The rigid limit: the distance falls at least 10× (K^{-3/2}: 1000×, floored by the
  // references' rtol 1e-9) from K = 1e9 to 1e11 and is then below 1e-5 m (the ball moves
  // ~1 m: a contact on the hub, a wrong sign or a missing modal force is off by centimetres).
  CHECK(distance[0] < 5e-4);
  CHECK(distance[1] < 0.1 * distance[0]);
  CHECK(distance[1] < 1e-5);
}

TEST_CASE("rigid limit and friction work: a block sliding down an incline on its node") {
  // Incline α = 0.3 rad, μ = 0.2 < tan α: the block accelerates down the slope at
  // g (sin α − μ cos α) from 1 m/s, sliding on a linear penalty contact started at its static
  // penetration m g cos α / k (no normal transient).
  const double alpha = 0.3, mu = 0.2, m = 2.0, k = 1e7;
  const Eigen::Vector3d n(-std::sin(alpha), 0.0, std::cos(alpha));
  const Eigen::Vector3d down(-std::cos(alpha), 0.0, -std::sin(alpha));
  const double delta0 = m * kG * std::cos(alpha) / k;
  const auto law = contact::NormalLaw::linear(k, 2.0 * std::sqrt(k * m));
  contact::FrictionLaw friction;
  friction.mu = mu;
  friction.v_reg = 1e-4;
  const auto build = [&](double K) {
    return particle(K, m, 0.0, -delta0 * n, 1.0 * down, Eigen::Vector3d::Zero(), n, law, friction);
  };
  const core::Model rigid = build(0.0);
  const core::Model flexible = build(1e9);
  reference::SolverOptions o;
  o.rtol = 1e-10;
  const std::vector<double> t = grid(1.0, 0.05);
  const reference::ReferenceRun a = reference::solve_cvode(rigid, t, o);
  const reference::ReferenceRun b = reference::solve_cvode(flexible, t, o);
  const double a_slope = kG * (std::sin(alpha) - mu * std::cos(alpha));
  for (std::size_t j = 0; j < t.size(); ++j) {
    const Eigen::Vector3d pr = centre(rigid, a.trajectory.states[j]);
    const Eigen::Vector3d pf = centre(flexible, b.trajectory.states[j]);
    // Rigid limit: the node carries m/2 on a spring K = 1e9: offsets m g/K ~ 2e-8 m.
    CHECK((pr - pf).norm() < 1e-6);
    // The exact sliding distance s(t) = t + ½ a t² (tanh(|v|/v_reg) = 1 to 1e-8000 at
    // |v| ≥ 1 m/s; the linear spring holds F_n = m g cos α exactly): the references to
    // 1e-8 m at rtol 1e-10 over a 1.3 m slide.
    const double s = t[j] + 0.5 * a_slope * t[j] * t[j];
    CHECK(std::abs((pr + delta0 * n).dot(down) - s) < 1e-7);
    // Friction work μ m g cos α s, the references' integrated wear work (a separate state
    // component, W' = |F_t·v_t|).
    const double expected = mu * m * kG * std::cos(alpha) * s;
    for (const reference::ReferenceRun* r : {&a, &b}) {
      const double wear = r->trajectory.extra_work[j];
      // Measured ≤ 1.7e-9 of W for both (rtol 1e-10 on a component that grows to 5.7 J, and the
      // stiff node's shear transient F_t/K ~ 1e-9 m); 1e-8 leaves room. A wrong friction
      // coefficient, normal force or slip speed is off by O(1) (the node's own slip velocity is
      // checked by node_attachment_test.cpp).
      CHECK(std::abs(wear - expected) <= 1e-8 * std::max(1.0, expected));
    }
  }
}

TEST_CASE("a modal oscillator hitting a stop: onset located by every reference, impacts, e") {
  // q̈ + q = 0 from q = 0, q̇ = 1 (m = 1, K = 1): the node reaches the stop at q = 1/2 at
  // t₁ = asin(1/2) = π/6 exactly, at speed √(1 − 1/4). Hunt–Crossley with e = 0.7 at that speed.
  const double v1 = std::sqrt(0.75);
  const auto build = [&] {
    core::RigidBodyDescription d = testing::modal_oscillator_body("osc", 1.0, 1.0, 1.0);
    contact::ContactPair pair = contact::ContactPair::point_plane(
        0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.0, 0.5), -Eigen::Vector3d::UnitZ());
    pair.node_b = testing::node_of(d, 0);
    Elements elements;
    elements.push_back(std::make_unique<contact::ContactElement>(
        std::vector<contact::ContactPair>{pair},
        contact::NormalLaw::hunt_crossley(1e9, 1.5, 0.7, v1), contact::FrictionLaw{}, 1.0, "stop"));
    std::vector<core::Body> bodies;
    bodies.emplace_back(d);
    return core::Model(std::move(bodies), std::move(elements));
  };
  const core::Model model = build();
  reference::SolverOptions o;
  o.rtol = 1e-10;
  const std::vector<double> t = grid(12.0, 0.5);
  using Solve = reference::ReferenceRun (*)(const core::Model&, const std::vector<double>&,
                                            const reference::SolverOptions&);
  for (const Solve solve : {&reference::solve_cvode, &reference::solve_ida,
                            &reference::solve_arkode, &reference::solve_odeint}) {
    const reference::ReferenceRun run = solve(model, t, o);
    INFO(run.solver);
    REQUIRE(run.event_times.size() >= 2);
    // Root location to the solver's tolerance: the state error ~ rtol·1 gives a time error
    // ~ rtol/v₁ ≈ 1e-10 s; 1e-8 s leaves room for the root finder's own tolerance.
    CHECK(std::abs(run.event_times.front() - std::numbers::pi / 6.0) < 1e-8);
    // Onsets and releases alternate and the run ends in free flight: impacts = events/2.
    // Each free flight lasts 2(π − asin(1/(2A))) ≥ 4.8 s for the amplitudes A ∈ [0.79, 1]
    // that e ∈ [0.7, 1] leaves, so the onsets are t₁, ≈ 5.5 and ≈ 10.4: three in [0, 12].
    CHECK(run.event_times.size() % 2 == 0);
    // Counts: small integers, exact in a double (no tolerance).
    CHECK(run.trajectory.impacts.back() == static_cast<double>(run.event_times.size()) / 2.0);
    CHECK(run.trajectory.impacts.back() == 3.0);
    CHECK(run.trajectory.impacts.front() == 0.0);
    if (solve != &reference::solve_cvode) continue;  // the restitution below: from CVODE's events
    // Restitution: speeds at the first two onsets (the free flight between them conserves
    // ½q̇² + ½q² and both are at q = 1/2). The law gives e = 0.7 exactly at v₁ without other
    // forces; the oscillator's spring K q ≈ 0.5 N acts during the ~1e-3 s contact and changes
    // the rebound speed by ≲ 2·0.5·1e-3/0.87 ≈ 1.2e-3 of v₁.
    const double t2 = run.event_times[2];
    const reference::ReferenceRun at =
        reference::solve_cvode(model, {0.0, run.event_times[0], t2}, o);
    const double s1 = std::abs(at.trajectory.states[1][0].qd_f(0));
    const double s2 = std::abs(at.trajectory.states[2][0].qd_f(0));
    CHECK(s1 == Approx(v1).epsilon(1e-8));
    CHECK(s2 / s1 == Approx(0.7).margin(3e-3));
  }
}

}  // namespace
}  // namespace flexref
