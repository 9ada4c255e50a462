/// Geometric stiffening (flexible/geometric_stiffness.hpp, docs/geometric_stiffening.md) at the
/// model level: the equations of motion follow from one Lagrangian, so for a free body without
/// loads the energy, the linear and the angular momentum computed by their own formulas
/// (Model::kinetic_energy, linear_momentum_W, angular_momentum_W: first_moment,
/// inertia_theta_theta, inertia_theta_f with the foreshortening) have zero rate along the model's
/// accelerations, at any state; a freely falling body carries no axial load (gravity's
/// foreshortening term against the mass matrix's); M is the Hessian of T; the rates are checked to
/// fail with a wrong sign.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "core/body.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "flexible/beam_model.hpp"
#include "flexible/geometric_stiffness.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/random_geometric_stiffness.hpp"

namespace flexref::core {
namespace {

using testing::random_vector;

/// Dense random modal data with all twelve geometric matrices non-zero (every term of the
/// stiffening enters), or a clamped-free beam off the origin with its own geometric stiffness.
flexible::ModalData random_stiffened_data(int N, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mass(0.1, 2.0);
  std::uniform_real_distribution<double> coordinate(-1.0, 2.0);
  flexible::ModalData data;
  data.mass.resize(N);
  data.p_BoNode_B.resize(3, N);
  for (int k = 0; k < N; ++k) {
    data.mass(k) = mass(rng);
    for (int a = 0; a < 3; ++a) data.p_BoNode_B(a, k) = coordinate(rng);
  }
  data.phi = 0.3 * Eigen::MatrixXd(random_vector(3 * N * n, rng, 1.0).reshaped(3 * N, n));
  data.stiffness = random_vector(n, rng, 10.0).cwiseAbs();
  data.damping_ratio = Eigen::VectorXd::Zero(n);
  data.geometric = testing::random_geometric_stiffness(n, rng);
  return data;
}

flexible::ModalData stiffened_beam() {
  flexible::BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.05, -0.02);
  p.elements = 8;
  p.EA = 1e5;
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  return flexible::make_beam_modal_data(p, 6, {}, flexible::BeamModeNormalization::kUnitModalMass,
                                        true);
}

Body free_body(flexible::ModalData data) {
  RigidBodyDescription d;
  d.name = "body";
  d.mass = 3.0;
  d.p_BoBcm_B = Eigen::Vector3d(0.05, -0.1, 0.02);
  d.I_Bcm_B = Eigen::Vector3d(0.3, 0.4, 0.5).asDiagonal();
  d.flexible = FlexiblePart{std::move(data), {}, {}};
  return Body(std::move(d));
}

/// A random state; modal coordinates of size q_size (the beam's unit-modal-mass modes move the
/// tip by about 2 q: 0.01 is a 2 % deflection, in the range of the second-order theory; at
/// q = 0.2 the truncated foreshortening makes the inertia of the 6-mode beam indefinite).
State random_state(const Model& model, std::mt19937& rng, double q_size = 0.2) {
  State s = model.initial_state();
  const Eigen::Index n = model.body(0).mode_count();
  s[0].p_WBr = random_vector(3, rng, 1.0);
  s[0].theta_WB = Eigen::Vector4d(random_vector(4, rng, 1.0)).normalized();
  s[0].v_WBr = random_vector(3, rng, 1.0);
  s[0].w_WB_B = random_vector(3, rng, 1.5);
  s[0].q_f = random_vector(n, rng, q_size);
  s[0].qd_f = random_vector(n, rng, 1.0);
  return s;
}

/// y + h ẏ along the model's own motion (attitude by the body-frame exponential).
State advanced(const State& s, const Accelerations& a, double h) {
  State out = s;
  out[0].p_WBr += h * s[0].v_WBr;
  out[0].theta_WB =
      rotation::quaternion_multiply(s[0].theta_WB, rotation::exp_quaternion(h * s[0].w_WB_B));
  out[0].v_WBr += h * a[0].a_WBr;
  out[0].w_WB_B += h * a[0].alpha_WB_B;
  out[0].q_f += h * s[0].qd_f;
  out[0].qd_f += h * a[0].qdd_f;
  return out;
}

struct Rates {
  double energy = 0.0, energy_scale = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), h = Eigen::Vector3d::Zero();
  double p_scale = 0.0, h_scale = 0.0;
};

/// Central differences (h = 1e-5) of E = T + V_el, p and H_O along the motion; `flip` reverses
/// the sign of the modal accelerations' stiffening share (a sign error in the test's model).
Rates rates(const Model& model, const State& s) {
  Workspace ws = model.make_workspace();
  Accelerations a(1);
  a[0].qdd_f.resize(model.body(0).mode_count());
  model.compute_accelerations({}, s, ws, a);
  const double h = 1e-5;
  const State plus = advanced(s, a, h), minus = advanced(s, a, -h);
  const auto energy = [&](const State& y) {
    return model.kinetic_energy(y) + model.potential_energy({}, y, ws);
  };
  Rates r;
  r.energy = (energy(plus) - energy(minus)) / (2.0 * h);
  r.energy_scale = model.kinetic_energy(s) * (s[0].w_WB_B.norm() + s[0].qd_f.norm() +
                                              a[0].alpha_WB_B.norm() + a[0].qdd_f.norm());
  r.p = (model.linear_momentum_W(plus) - model.linear_momentum_W(minus)) / (2.0 * h);
  r.h = (model.angular_momentum_W(plus) - model.angular_momentum_W(minus)) / (2.0 * h);
  r.p_scale = model.linear_momentum_W(s).norm() + model.body(0).mass() * a[0].a_WBr.norm();
  r.h_scale =
      model.angular_momentum_W(s).norm() * (1.0 + s[0].w_WB_B.norm() + a[0].alpha_WB_B.norm());
  return r;
}

TEST_CASE("geometric stiffening: energy and momenta of a free body have zero rate",
          "[core][flexible][geometric]") {
  // The rates are central differences with h = 1e-5: truncation O(h²) ≈ 1e-10 and rounding
  // ≈ ε/h ≈ 2e-11 of the quantities' scales; 1e-7 of the scale leaves three orders of margin,
  // while a stiffening term with the wrong sign changes the rates by O(1) of the stiffening's
  // share (checked below).
  for (const unsigned seed : {1u, 2u, 3u}) {
    for (const bool beam : {false, true}) {
      const Model model = [&] {
        std::vector<Body> bodies;
        bodies.push_back(free_body(beam ? stiffened_beam() : random_stiffened_data(9, 4, seed)));
        return Model(std::move(bodies), {});
      }();
      REQUIRE(model.body(0).invariants().geometric.has_value());
      std::mt19937 rng(100 + seed);
      const State s = random_state(model, rng, beam ? 0.01 : 0.2);
      const Rates r = rates(model, s);
      INFO((beam ? "beam" : "random data")
           << " seed " << seed << ": dE/dt " << r.energy << " (scale " << r.energy_scale
           << "), dp/dt " << r.p.transpose() << ", dH/dt " << r.h.transpose());
      CHECK(std::abs(r.energy) <= 1e-7 * r.energy_scale);
      CHECK(r.p.norm() <= 1e-7 * r.p_scale);
      CHECK(r.h.norm() <= 1e-7 * r.h_scale);
    }
  }
}

TEST_CASE("geometric stiffening: a pivoted body conserves energy and its angular momentum",
          "[core][flexible][geometric]") {
  // A pivot at the world origin: the reaction does no work and has no moment about it, so E
  // and H_O = H_pivot are invariants (the translation rows are known, a = 0); bounds as above.
  for (const bool beam : {false, true}) {
    RigidBodyDescription d;
    d.name = "body";
    d.mass = 3.0;
    d.p_BoBcm_B = Eigen::Vector3d(0.05, -0.1, 0.02);
    d.I_Bcm_B = Eigen::Vector3d(0.3, 0.4, 0.5).asDiagonal();
    d.motion = MotionKind::kPivot;
    d.p_BoPivot_B = Eigen::Vector3d(-0.2, 0.1, 0.05);
    d.flexible = FlexiblePart{beam ? stiffened_beam() : random_stiffened_data(9, 4, 4), {}, {}};
    std::vector<Body> bodies;
    bodies.emplace_back(std::move(d));
    const Model model(std::move(bodies), {});
    std::mt19937 rng(beam ? 21 : 22);
    State s = random_state(model, rng, beam ? 0.01 : 0.2);
    s[0].p_WBr.setZero();
    s[0].v_WBr.setZero();
    const Rates r = rates(model, s);
    INFO((beam ? "beam" : "random data") << ": dE/dt " << r.energy << " (scale " << r.energy_scale
                                         << "), dH/dt " << r.h.transpose());
    CHECK(std::abs(r.energy) <= 1e-7 * r.energy_scale);
    CHECK(r.h.norm() <= 1e-7 * r.h_scale);
  }
}

TEST_CASE("geometric stiffening: the conservation check fails with a wrong sign",
          "[core][flexible][geometric]") {
  // Negating every geometric matrix is not a sign error (a consistent Lagrangian, still
  // conservative); dropping the stiffening from the kinetic energy while keeping it in the
  // equations is: the energy of the classical model is not conserved by the stiffened motion.
  flexible::ModalData data = random_stiffened_data(9, 4, 5);
  std::vector<Body> with;
  with.push_back(free_body(data));
  const Model stiffened(std::move(with), {});
  data.geometric.reset();
  std::vector<Body> without;
  without.push_back(free_body(data));
  const Model classical(std::move(without), {});
  std::mt19937 rng(7);
  const State s = random_state(stiffened, rng);
  Workspace ws = stiffened.make_workspace();
  Accelerations a(1);
  a[0].qdd_f.resize(4);
  stiffened.compute_accelerations({}, s, ws, a);
  const double h = 1e-5;
  const auto energy = [&](const State& y) {
    return classical.kinetic_energy(y) + classical.potential_energy({}, y, ws);
  };
  const double rate = (energy(advanced(s, a, h)) - energy(advanced(s, a, -h))) / (2.0 * h);
  const Rates good = rates(stiffened, s);
  INFO("classical energy's rate along the stiffened motion " << rate << " (scale "
                                                             << good.energy_scale << ")");
  CHECK(std::abs(rate) > 1e-3 * good.energy_scale);
}

TEST_CASE("geometric stiffening: a freely falling body carries no axial load",
          "[core][flexible][geometric]") {
  // Equivalence principle: uniform gravity accelerates every node alike, so the modal
  // accelerations are those without gravity; only if gravity's foreshortening work ΔSᵀAᵀg
  // (core/gravity_impl.hpp) balances the mass matrix's coupling A ΔS(q_f) (GS-8's a0 term). 1e-10
  // relative: the two evaluations differ by the rounding of the g-terms (|g| ≈ 10 against
  // accelerations of O(10)) through the solve, ≈ 1e3 ε; without the balance q̈ changes by
  // |g| |E_x q_f| / μ ≈ 1.
  const flexible::ModalData data = stiffened_beam();
  const auto make = [&](bool gravity) {
    std::vector<Body> bodies;
    bodies.push_back(free_body(data));
    std::vector<std::unique_ptr<const ForceElement>> elements;
    if (gravity) {
      const double m = bodies[0].mass();
      elements.push_back(std::make_unique<UniformGravity>(
          Eigen::Vector3d(3.0, -9.81, 2.0),
          std::vector<UniformGravity::BodyMass>{{0, m, Eigen::Vector3d::Zero()}}));
    }
    return Model(std::move(bodies), std::move(elements));
  };
  const Model free = make(false), falling = make(true);
  std::mt19937 rng(9);
  State s = random_state(free, rng, 0.01);
  Workspace ws1 = free.make_workspace(), ws2 = falling.make_workspace();
  Accelerations a1(1), a2(1);
  a1[0].qdd_f.resize(6);
  a2[0].qdd_f.resize(6);
  free.compute_accelerations({}, s, ws1, a1);
  falling.compute_accelerations({}, s, ws2, a2);
  INFO("q̈ without gravity " << a1[0].qdd_f.transpose() << "; with " << a2[0].qdd_f.transpose());
  CHECK((a1[0].qdd_f - a2[0].qdd_f).norm() <= 1e-10 * (1.0 + a1[0].qdd_f.norm()));
  CHECK((a1[0].alpha_WB_B - a2[0].alpha_WB_B).norm() <= 1e-10 * (1.0 + a1[0].alpha_WB_B.norm()));
  CHECK((a2[0].a_WBr - a1[0].a_WBr - Eigen::Vector3d(3.0, -9.81, 2.0)).norm() <= 1e-10);
}

TEST_CASE("geometric stiffening: off, or zero data, changes nothing",
          "[core][flexible][geometric]") {
  // The stiffened code path with all-zero matrices gives the classical model's accelerations
  // to rounding, and the beam without the option carries no geometric data at all.
  flexible::BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  p.elements = 6;
  const flexible::ModalData plain = flexible::make_beam_modal_data(p, 4);
  CHECK_FALSE(plain.geometric.has_value());
  flexible::ModalData zero = plain;
  zero.geometric.emplace();
  for (auto& M : zero.geometric->E) M = Eigen::MatrixXd::Zero(4, 4);
  for (auto& M : zero.geometric->F) M = Eigen::MatrixXd::Zero(4, 4);
  std::vector<Body> b1, b2;
  b1.push_back(free_body(plain));
  b2.push_back(free_body(zero));
  const Model m1(std::move(b1), {}), m2(std::move(b2), {});
  std::mt19937 rng(11);
  const State s = random_state(m1, rng);
  Workspace w1 = m1.make_workspace(), w2 = m2.make_workspace();
  Accelerations a1(1), a2(1);
  a1[0].qdd_f.resize(4);
  a2[0].qdd_f.resize(4);
  m1.compute_accelerations({}, s, w1, a1);
  m2.compute_accelerations({}, s, w2, a2);
  // The structured solve takes another (forward-substitution) route for the translation rows.
  CHECK((a1[0].qdd_f - a2[0].qdd_f).norm() <= 1e-12 * a1[0].qdd_f.norm());
  CHECK((a1[0].alpha_WB_B - a2[0].alpha_WB_B).norm() <= 1e-12 * a1[0].alpha_WB_B.norm());
  CHECK(m1.kinetic_energy(s) == m2.kinetic_energy(s));
}

}  // namespace
}  // namespace flexref::core
