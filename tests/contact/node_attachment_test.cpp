/// Generalized forces of loads and contacts at deforming points (core/node_attachment.hpp,
/// contact/contact.hpp with nodes, contact/gap_support.hpp), against central differences of
/// the potential they derive from: with zero velocities (δ̇ = 0) and no friction each contact's
/// force is the elastic −∇V, and a constant force f at a point P is −∇ of V = −f·p_WP. Every
/// component — the force on Br, the torque about Br from the deformed arm, the modal rows
/// Φ_kᵀ Aᵀ f — is compared, so a sign error or an undeformed arm fails. Positions of nodes in
/// the differences come from Model::p_WP of a tracked node point (Body::p_BrP_B), a code path
/// independent of the attachment's.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "contact/contact.hpp"
#include "contact/gap_support.hpp"
#include "core/applied_load.hpp"
#include "core/model.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/node_contact_models.hpp"

namespace flexref {
namespace {

using testing::beam_bending_modes;
using testing::flexible_body;

constexpr int kNode = 7;  // a node of the beam at x ≈ 0.7 (10 elements, Gauss–Lobatto points)

/// A free flexible body (hub m = 10 plus a clamped-free beam with 4 bending modes), deformed,
/// rotated and moving, and a rigid ball.
std::vector<core::Body> bodies() {
  core::RigidBodyDescription beam = flexible_body(
      "beam", beam_bending_modes(Eigen::Vector3d(0.1, 0.0, 0.0), 1.0, 3.2, 1e5, 1.0, 10, 4));
  beam.mass = 10.0;
  beam.I_Bcm_B = Eigen::Vector3d(0.5, 0.5, 1.0).asDiagonal();
  beam.flexible->q0 = Eigen::Vector4d(0.03, -0.02, 0.015, 0.01);
  beam.initial.theta_WB = rotation::exp_quaternion(Eigen::Vector3d(0.3, -0.2, 0.5));
  beam.initial.p_WBo = Eigen::Vector3d(0.2, -0.1, 0.4);
  core::RigidBodyDescription ball;
  ball.name = "ball";
  ball.mass = 2.0;
  ball.I_Bcm_B = Eigen::Matrix3d::Identity() * 0.01;
  std::vector<core::Body> out;
  out.emplace_back(beam);
  out.emplace_back(ball);
  return out;
}

/// The state's world position of the beam node (deformed), by the tracked-point path.
Eigen::Vector3d node_position(const core::Model& m, const core::State& s) {
  return m.p_WP(0, s[0],
                core::TrackedPoint{
                    "n", m.body(0).description().flexible->modal.p_BoNode_B.col(kNode), kNode});
}

struct Loads {
  Eigen::Vector3d f_W, tau_W;
  Eigen::VectorXd Q_f;
};

Loads loads_of(const core::Model& m, const core::State& s, int body) {
  core::Workspace ws = m.make_workspace();
  m.compute_wrenches(core::LoadContext{0.0, 0.0}, s, ws);
  const core::Wrench& w = ws.wrenches[static_cast<std::size_t>(body)];
  return {w.f_W, w.tau_Br_W, w.Q_f};
}

/// −∂V/∂(p_WBr, rotation about Br in world, q_f) of body `body` by central differences,
/// with V = `potential`(state).
template <class Potential>
Loads minus_gradient(const core::State& s0, int body, const Potential& potential) {
  const double h = 1e-6;
  Loads g;
  const auto b = static_cast<std::size_t>(body);
  g.Q_f = Eigen::VectorXd::Zero(s0[b].q_f.size());
  for (int i = 0; i < 3; ++i) {
    core::State plus = s0, minus = s0;
    plus[b].p_WBr(i) += h;
    minus[b].p_WBr(i) -= h;
    g.f_W(i) = -(potential(plus) - potential(minus)) / (2.0 * h);
    Eigen::Vector3d phi = Eigen::Vector3d::Zero();
    phi(i) = h;
    plus = s0;
    minus = s0;
    plus[b].theta_WB = rotation::quaternion_multiply(rotation::exp_quaternion(phi), s0[b].theta_WB);
    minus[b].theta_WB =
        rotation::quaternion_multiply(rotation::exp_quaternion(-phi), s0[b].theta_WB);
    g.tau_W(i) = -(potential(plus) - potential(minus)) / (2.0 * h);
  }
  for (Eigen::Index k = 0; k < g.Q_f.size(); ++k) {
    core::State plus = s0, minus = s0;
    plus[b].q_f(k) += h;
    minus[b].q_f(k) -= h;
    g.Q_f(k) = -(potential(plus) - potential(minus)) / (2.0 * h);
  }
  return g;
}

/// Central differences with h = 1e-6 on forces of O(10–1000) N over lengths O(1): truncation
/// error h² V''' ~ 1e-12·(k δ^{n−2}) and rounding ε V/h ~ 1e-10 V; compared relative to the
/// largest component with 1e-6 (both far below; a sign error or a missing term is O(1)).
void require_equal(const Loads& a, const Loads& b) {
  const double scale = std::max({a.f_W.norm(), a.tau_W.norm(), a.Q_f.norm(), 1e-12});
  CHECK((a.f_W - b.f_W).norm() <= 1e-6 * scale);
  CHECK((a.tau_W - b.tau_W).norm() <= 1e-6 * scale);
  CHECK((a.Q_f - b.Q_f).norm() <= 1e-6 * scale);
  CHECK(a.Q_f.norm() > 1e-3 * scale);  // the node's modal force is really there
}

core::Model model_with(std::unique_ptr<const core::ForceElement> e,
                       core::FlexibleFormulation f = core::FlexibleFormulation::kCoupled) {
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::move(e));
  return core::Model(bodies(), std::move(elements), f);
}

double contact_potential(const core::Model& m, const core::State& s) {
  core::Workspace ws = m.make_workspace();
  return m.potential_energy(core::LoadContext{0.0, 0.0}, s, ws) - m.elastic_energy(s);
}

contact::NormalLaw law() { return contact::NormalLaw::hunt_crossley(1e6, 1.5, 0.5, 1.0); }

TEST_CASE("sphere-plane contact at a node: force, deformed-arm torque and Φᵀ Aᵀ f are −∇V") {
  const std::vector<core::Body> b = bodies();
  const core::NodeAttachment node = testing::node_of(b[0].description(), kNode);
  // The plane through the deformed node shifted by 1 cm along n: δ = r − 0.01 = 0.02 m.
  core::Model probe = model_with(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d::Zero(), core::LoadFrame::kWorld, core::TimeProfile::constant()));
  const core::State s = probe.initial_state();
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  const Eigen::Vector3d p_node = node_position(probe, s);
  contact::ContactPair pair = contact::ContactPair::sphere_plane(
      0, b[0].description().flexible->modal.p_BoNode_B.col(kNode), 0.03, p_node - 0.01 * n, n);
  pair.node_b = node;
  const core::Model m = model_with(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{pair}, law(), contact::FrictionLaw{}));
  const Loads analytic = loads_of(m, s, 0);
  const Loads numeric =
      minus_gradient(s, 0, [&](const core::State& x) { return contact_potential(m, x); });
  require_equal(analytic, numeric);

  SECTION("the LTE model's contact sees the same deformed node") {
    const core::Model lte =
        model_with(std::make_unique<contact::ContactElement>(
                       std::vector<contact::ContactPair>{pair}, law(), contact::FrictionLaw{}),
                   core::FlexibleFormulation::kLte);
    const Loads l = loads_of(lte, s, 0);
    CHECK((l.f_W - analytic.f_W).norm() == 0.0);
    CHECK((l.tau_W - analytic.tau_W).norm() == 0.0);
    CHECK((l.Q_f - analytic.Q_f).norm() == 0.0);
  }
  SECTION("a hub sphere at the same undeformed point has no modal force and another gap") {
    contact::ContactPair hub = pair;
    hub.node_b = {};
    const core::Model mh = model_with(std::make_unique<contact::ContactElement>(
        std::vector<contact::ContactPair>{hub}, law(), contact::FrictionLaw{}));
    CHECK(loads_of(mh, s, 0).Q_f.norm() == 0.0);
  }
}

TEST_CASE("sphere-sphere contact between a node and a rigid ball: both bodies get −∇V") {
  std::vector<core::Body> b = bodies();
  const core::NodeAttachment node = testing::node_of(b[0].description(), kNode);
  core::Model probe = model_with(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d::Zero(), core::LoadFrame::kWorld, core::TimeProfile::constant()));
  core::State s = probe.initial_state();
  const Eigen::Vector3d p_node = node_position(probe, s);
  // The ball's centre 0.07 from the node: radii 0.03 + 0.05 overlap by 1 cm.
  s[1].p_WBr = p_node + 0.07 * Eigen::Vector3d(0.6, 0.0, 0.8);
  const contact::ContactPair pair = [&] {
    contact::ContactPair p = contact::ContactPair::sphere_sphere(
        0, b[0].description().flexible->modal.p_BoNode_B.col(kNode), 0.03, 1,
        Eigen::Vector3d::Zero(), 0.05);
    p.node_a = node;
    return p;
  }();
  const core::Model m = model_with(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{pair}, law(), contact::FrictionLaw{}));
  const auto V = [&](const core::State& x) { return contact_potential(m, x); };
  require_equal(loads_of(m, s, 0), minus_gradient(s, 0, V));
  const Loads ball = loads_of(m, s, 1);
  const Loads ball_numeric = minus_gradient(s, 1, V);
  CHECK((ball.f_W - ball_numeric.f_W).norm() <= 1e-6 * ball.f_W.norm());
  CHECK(ball.f_W.dot(Eigen::Vector3d(0.6, 0.0, 0.8)) > 0.0);  // pushed away from the node
}

TEST_CASE("gap support at a node: circular and planar clearance forces are −∇V") {
  std::vector<core::Body> b = bodies();
  const core::NodeAttachment node = testing::node_of(b[0].description(), kNode);
  core::Model probe = model_with(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d::Zero(), core::LoadFrame::kWorld, core::TimeProfile::constant()));
  const core::State s = probe.initial_state();
  const Eigen::Vector3d p_node = node_position(probe, s);
  const Eigen::Vector3d a = Eigen::Vector3d(1.0, 0.2, -0.1).normalized();
  // The axis 3 mm from the node, clearance 1 mm: δ = 2 mm.
  const Eigen::Vector3d off = a.cross(Eigen::Vector3d::UnitZ()).normalized();
  for (const bool circular : {true, false}) {
    contact::GapSupportGeometry g;
    g.kind = circular ? contact::GapSupportGeometry::Kind::kCircular
                      : contact::GapSupportGeometry::Kind::kPlanar;
    g.a_W = a;
    g.m_W = off + 0.3 * a;  // projected across the axis by the constructor
    g.p_WS = p_node - 0.003 * off + 0.2 * a;
    g.clearance = 0.001;
    const core::Model m = model_with(std::make_unique<contact::GapSupport>(
        0, b[0].description().flexible->modal.p_BoNode_B.col(kNode), node, g, law(),
        contact::FrictionLaw{}, 0.0, "support"));
    core::Workspace ws = m.make_workspace();
    std::vector<double> gap(1);
    m.switching_functions(core::LoadContext{0.0, 0.0}, s, ws, gap);
    // The node is 3 mm from the axis (exactly: the offset is normal to a) with 1 mm clearance.
    CHECK(gap[0] == Approx(-0.002).margin(1e-12));
    const Loads analytic = loads_of(m, s, 0);
    require_equal(analytic, minus_gradient(s, 0, [&](const core::State& x) {
                    return contact_potential(m, x);
                  }));
    // Pushed back toward the axis.
    CHECK(analytic.f_W.dot(off) < 0.0);
  }
}

TEST_CASE("a constant force at a node: Φ_kᵀ Aᵀ f and the deformed arm are −∇(−f·p_WP)") {
  const std::vector<core::Body> b = bodies();
  const Eigen::Vector3d f(3.0, -2.0, 5.0);
  const core::Model m = model_with(std::make_unique<core::AppliedForce>(
      0, f, core::LoadFrame::kWorld, b[0].description().flexible->modal.p_BoNode_B.col(kNode),
      core::TimeProfile::constant(), testing::node_of(b[0].description(), kNode)));
  const core::State s = m.initial_state();
  require_equal(loads_of(m, s, 0), minus_gradient(s, 0, [&](const core::State& x) {
                  return -f.dot(node_position(m, x));
                }));
}

TEST_CASE("the attached point's velocity is the time derivative of its deformed position") {
  std::vector<core::Body> b = bodies();
  const core::NodeAttachment node = testing::node_of(b[0].description(), kNode);
  core::Model m = model_with(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d::Zero(), core::LoadFrame::kWorld, core::TimeProfile::constant()));
  core::State s = m.initial_state();
  s[0].v_WBr = Eigen::Vector3d(0.3, -0.7, 0.2);
  s[0].w_WB_B = Eigen::Vector3d(1.1, -0.4, 2.0);
  s[0].qd_f = Eigen::Vector4d(0.5, -0.8, 0.3, 0.9);
  core::Workspace ws = m.make_workspace();
  m.compute_wrenches(core::LoadContext{0.0, 0.0}, s, ws);
  const Eigen::Vector3d x_P = b[0].description().flexible->modal.p_BoNode_B.col(kNode);
  const Eigen::Vector3d p = core::attached_position_W(ws.kinematics[0], x_P, node);
  // The same point by two routes (the attachment's and the model's): a rotation and two sums,
  // a few roundings of ε |p| each; 10 × 1e-15 |p| ≈ 45 ε |p| bounds them.
  CHECK((p - node_position(m, s)).norm() <= 1e-15 * p.norm() * 10);
  const Eigen::Vector3d v = core::attached_velocity_W(ws.kinematics[0], p, node);
  // Move along the state's velocities by ±h: p_WBr + h v, θ ⊗ exp(h ω̄), q + h q̇.
  const double h = 1e-6;
  const auto moved = [&](double dt) {
    core::State x = s;
    x[0].p_WBr += dt * s[0].v_WBr;
    x[0].theta_WB =
        rotation::quaternion_multiply(s[0].theta_WB, rotation::exp_quaternion(dt * s[0].w_WB_B));
    x[0].q_f += dt * s[0].qd_f;
    return node_position(m, x);
  };
  const Eigen::Vector3d v_numeric = (moved(h) - moved(-h)) / (2.0 * h);
  // O(h²) truncation (|p'''| ~ 10 m/s³ → 1e-11) and rounding ε/h ~ 1e-10 m/s.
  CHECK((v - v_numeric).norm() <= 1e-8);
  CHECK(core::NodeAttachment{}.shape_for(s[0].q_f.size()) == nullptr);  // a hub point: Φ = 0
}

}  // namespace
}  // namespace flexref
