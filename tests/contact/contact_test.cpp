/// Contact geometry and laws (contact/contact.hpp, contact/contact_laws.hpp): gaps and contact
/// points, forces against finite differences of the penalty potential, wrench consistency, the
/// directions and power of damping and friction, the Hunt–Crossley restitution relation
/// against a direct integration of the impact, and allocation-free evaluation.
#include "contact/contact.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"
#include "tests/support/allocation_counting.hpp"

namespace flexref::core {
namespace {

/// Two bodies at random poses and velocities (fixed seed), with the frame origin Bo away from
/// the reference point Br so that arms from Bo and from Br differ.
struct TwoBodies {
  std::array<BodyState, 2> states;
  std::array<BodyKinematics, 2> kinematics;

  explicit TwoBodies(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto vec = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
    for (std::size_t i = 0; i < 2; ++i) {
      states[i].p_WBr = vec();
      states[i].theta_WB = rotation::exp_quaternion(2.0 * vec());
      states[i].v_WBr = vec();
      states[i].w_WB_B = 3.0 * vec();
      kinematics[i].state = &states[i];
      kinematics[i].R_WB = rotation::rotation_matrix(states[i].theta_WB);
      kinematics[i].p_BoBr_B = 0.3 * vec();
    }
  }
  /// Copies point their kinematics at their own states.
  TwoBodies(const TwoBodies& other) : states(other.states), kinematics(other.kinematics) {
    for (std::size_t i = 0; i < 2; ++i) kinematics[i].state = &states[i];
  }
  TwoBodies& operator=(const TwoBodies&) = delete;
  std::span<const BodyKinematics> span() const { return kinematics; }
  void scale_velocities(double factor) {
    for (BodyState& s : states) {
      s.v_WBr *= factor;
      s.w_WB_B *= factor;
    }
  }
  void set_rest() {
    for (BodyState& s : states) {
      s.v_WBr.setZero();
      s.w_WB_B.setZero();
    }
  }
};

/// Body point (from Bo, body frame) that lies at world point p_W for body i.
Eigen::Vector3d body_point_at(const BodyKinematics& k, const Eigen::Vector3d& p_W) {
  return k.p_BoBr_B + k.R_WB.transpose() * (p_W - k.state->p_WBr);
}

std::array<Wrench, 2> wrenches_of(const contact::ContactElement& c, const TwoBodies& b) {
  std::array<Wrench, 2> w;
  c.add_wrenches({0.0, 0.0}, b.span(), w);
  return w;
}

/// A sphere–plane pair placed so that the sphere penetrates the plane by `depth` at body 0's
/// random pose: the plane's normal and point are chosen from the pose.
contact::ContactPair penetrating_sphere_plane(const TwoBodies& b, double radius, double depth,
                                              const Eigen::Vector3d& n_W) {
  const Eigen::Vector3d p_BoC_B(0.2, -0.1, 0.15);
  const Eigen::Vector3d p_WC = b.kinematics[0].p_WP(p_BoC_B);
  const Eigen::Vector3d p_WQ = p_WC - (radius - depth) * n_W.normalized();
  return contact::ContactPair::sphere_plane(0, p_BoC_B, radius, p_WQ, n_W);
}

/// A sphere–sphere pair between bodies 0 (a) and 1 (b) with the given gap at the random poses.
contact::ContactPair sphere_pair(const TwoBodies& b, double r_a, double r_b, double gap) {
  const Eigen::Vector3d p_BoCa_B(-0.1, 0.2, 0.05);
  const Eigen::Vector3d p_WCa = b.kinematics[0].p_WP(p_BoCa_B);
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const Eigen::Vector3d p_WCb = p_WCa + (r_a + r_b + gap) * dir;
  return contact::ContactPair::sphere_sphere(0, p_BoCa_B, r_a, 1,
                                             body_point_at(b.kinematics[1], p_WCb), r_b);
}

TEST_CASE("contact geometry: gaps, normals and contact points by hand", "[core][contact]") {
  // A unit-free hand case: body 0 at (1, 2, 3) rotated by +90° about z (x_B → y_W); sphere
  // centre at body (0.5, 0, 0) from Bo = Br → world (1, 2.5, 3). Plane z = 2.8, normal +z:
  // gap = 3 − 2.8 − 0.25 = −0.05, P = (1, 2.5, 2.75).
  BodyState s;
  s.p_WBr = Eigen::Vector3d(1, 2, 3);
  s.theta_WB = rotation::exp_quaternion(Eigen::Vector3d(0, 0, std::numbers::pi / 2));
  BodyKinematics k;
  k.state = &s;
  k.R_WB = rotation::rotation_matrix(s.theta_WB);
  const std::array<BodyKinematics, 1> one{k};
  const contact::ContactPair plane = contact::ContactPair::sphere_plane(
      0, Eigen::Vector3d(0.5, 0, 0), 0.25, Eigen::Vector3d(7, -3, 2.8),
      Eigen::Vector3d(0, 0, 2));  // normalized
  const contact::ContactPoint c = contact_point(plane, one);
  // Rotation by exp_quaternion rounds at ~1e-16; 1e-14 leaves two decades.
  CHECK(c.gap == Approx(-0.05).margin(1e-14));
  CHECK((c.p_WP - Eigen::Vector3d(1, 2.5, 2.75)).norm() < 1e-14);
  CHECK((c.n_W - Eigen::Vector3d::UnitZ()).norm() < 1e-15);
  // A point contact (r = 0) at the same body point: gap 0.2, P the point itself.
  const contact::ContactPoint p = contact_point(
      contact::ContactPair::point_plane(0, Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0, 0, 2.8),
                                        Eigen::Vector3d::UnitZ()),
      one);
  CHECK(p.gap == Approx(0.2).margin(1e-14));
  CHECK((p.p_WP - Eigen::Vector3d(1, 2.5, 3)).norm() < 1e-14);

  // Two spheres on the x axis: centres 0 and 1, radii 0.3 and 0.5 → gap 0.2, n = +x,
  // P = 0.3 + 0.1 = 0.4 (midway between the surfaces at 0.3 and 0.5).
  BodyState s2;
  s2.p_WBr = Eigen::Vector3d(1, 0, 0);
  BodyState s1;
  BodyKinematics k1, k2;
  k1.state = &s1;
  k2.state = &s2;
  const std::array<BodyKinematics, 2> two{k1, k2};
  const contact::ContactPoint cs =
      contact_point(contact::ContactPair::sphere_sphere(0, Eigen::Vector3d::Zero(), 0.3, 1,
                                                        Eigen::Vector3d::Zero(), 0.5),
                    two);
  CHECK(cs.gap == Approx(0.2).margin(1e-15));
  CHECK((cs.n_W - Eigen::Vector3d::UnitX()).norm() < 1e-15);
  CHECK((cs.p_WP - Eigen::Vector3d(0.4, 0, 0)).norm() < 1e-15);
}

TEST_CASE("contact geometry at random poses", "[core][contact]") {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const TwoBodies b(seed);
    const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.4, 1.0).normalized();
    const double gap = 0.3 * (static_cast<double>(seed) / 10.0 - 1.0);  // −0.27 … +0.3
    // Sphere–plane: the pair is placed with gap = −depth; P is on the sphere (|P − C| = r)
    // and its signed distance to the plane is the gap. Sums of O(1) terms: 1e-14.
    const contact::ContactPair sp = penetrating_sphere_plane(b, 0.4, -gap, n);
    const contact::ContactPoint c = contact_point(sp, b.span());
    const Eigen::Vector3d p_WC = b.kinematics[0].p_WP(sp.p_BoCb_B);
    CHECK(c.gap == Approx(gap).margin(1e-14));
    CHECK((c.p_WP - p_WC).norm() == Approx(0.4).margin(1e-14));
    CHECK(n.dot(c.p_WP - sp.p_WQ) == Approx(gap).margin(1e-14));
    // Sphere–sphere: P is on the centre line at r_a + g/2 from C_a and r_b + g/2 from C_b.
    const contact::ContactPair ss = sphere_pair(b, 0.25, 0.35, gap);
    const contact::ContactPoint d = contact_point(ss, b.span());
    const Eigen::Vector3d p_WCa = b.kinematics[0].p_WP(ss.p_BoCa_B);
    const Eigen::Vector3d p_WCb = b.kinematics[1].p_WP(ss.p_BoCb_B);
    CHECK(d.gap == Approx(gap).margin(1e-14));
    CHECK((d.p_WP - p_WCa).norm() == Approx(0.25 + 0.5 * gap).margin(1e-14));
    CHECK((d.p_WP - p_WCb).norm() == Approx(0.35 + 0.5 * gap).margin(1e-14));
    CHECK((p_WCb - p_WCa).normalized().dot(d.n_W) == Approx(1.0).margin(1e-15));
  }
}

/// The laws every force check runs with: linear (k = 2e3 N/m, damped) and Hunt–Crossley with
/// n = 1.5 and n = 1.2, all with friction.
std::vector<contact::NormalLaw> laws() {
  return {contact::NormalLaw::linear(2e3, 15.0),
          contact::NormalLaw::hunt_crossley(5e4, 1.5, 0.6, 1.0),
          contact::NormalLaw::hunt_crossley(3e4, 1.2, 0.3, 2.0)};
}

TEST_CASE("elastic contact forces are minus the gradient of the penalty energy",
          "[core][contact]") {
  // At rest (no damping, no friction) the wrench is the elastic one. Central differences of V
  // in the position of Br and in a world rotation increment φ about Br (R → exp(φ̂) R): the
  // force is −∂V/∂p and the torque about Br −∂V/∂φ. Step h = 1e-6 ≪ δ = 0.02 keeps every
  // sample on the smooth branch; error h² V'''/6 ~ 1e-12·k δⁿ⁻² ≲ 1e-6 N against forces of
  // ~10–100 N, plus round-off ε V/h ~ 1e-10: 1e-6 relative to the force scale.
  const double h = 1e-6;
  for (const contact::NormalLaw& law : laws()) {
    for (unsigned seed = 30; seed < 35; ++seed) {
      TwoBodies b(seed);
      b.set_rest();
      const Eigen::Vector3d n = Eigen::Vector3d(0.2 * seed - 6.4, 0.3, 1.0).normalized();
      const contact::ContactElement element(
          {penetrating_sphere_plane(b, 0.1, 0.02, n), sphere_pair(b, 0.2, 0.15, -0.02)}, law,
          contact::FrictionLaw{0.5, 1e-3});
      const std::array<Wrench, 2> w = wrenches_of(element, b);
      double scale = 0.0;
      for (const Wrench& x : w) scale = std::max({scale, x.f_W.norm(), x.tau_Br_W.norm()});
      REQUIRE(scale > 1.0);  // the pairs do penetrate
      for (std::size_t i = 0; i < 2; ++i) {
        for (int axis = 0; axis < 3; ++axis) {
          const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(axis);
          auto energy_shifted = [&](double sign) {
            TwoBodies moved = b;
            moved.states[i].p_WBr += sign * e;
            return element.potential_energy({0.0, 0.0}, moved.span());
          };
          auto energy_rotated = [&](double sign) {
            TwoBodies moved = b;
            moved.kinematics[i].R_WB = rotation::exp_so3(sign * e) * b.kinematics[i].R_WB;
            return element.potential_energy({0.0, 0.0}, moved.span());
          };
          const double force = -(energy_shifted(1.0) - energy_shifted(-1.0)) / (2.0 * h);
          const double torque = -(energy_rotated(1.0) - energy_rotated(-1.0)) / (2.0 * h);
          CHECK(std::abs(force - w[i].f_W(axis)) < 1e-6 * scale);
          CHECK(std::abs(torque - w[i].tau_Br_W(axis)) < 1e-6 * scale);
        }
      }
    }
  }
}

TEST_CASE("contact wrenches: torque is arm × force, action equals reaction", "[core][contact]") {
  for (const contact::NormalLaw& law : laws()) {
    for (unsigned seed = 40; seed < 45; ++seed) {
      TwoBodies b(seed);
      b.scale_velocities(0.1);  // slow enough that the clamp does not release the contact
      const contact::ContactElement element({sphere_pair(b, 0.2, 0.15, -0.03)}, law,
                                            contact::FrictionLaw{0.4, 0.05});
      const contact::ContactEvaluation e = element.evaluate(0, b.span());
      const std::array<Wrench, 2> w = wrenches_of(element, b);
      const Eigen::Vector3d f = e.force_on_b_W();
      REQUIRE(f.norm() > 1.0);
      // One force at one point: f_b = f, f_a = −f, τ_i = (P − p_WBr,i) × f_i. Products of O(1)
      // arms and O(10–100) N forces: 1e-12 relative.
      const double tol = 1e-12 * f.norm();
      CHECK((w[1].f_W - f).norm() < tol);
      CHECK((w[0].f_W + f).norm() < tol);
      CHECK((w[1].tau_Br_W - (e.point.p_WP - b.states[1].p_WBr).cross(f)).norm() < tol);
      CHECK((w[0].tau_Br_W + (e.point.p_WP - b.states[0].p_WBr).cross(f)).norm() < tol);
      // Plane pair on body 0 alone: body 1 gets nothing.
      const contact::ContactElement plane(
          {penetrating_sphere_plane(b, 0.1, 0.01, Eigen::Vector3d::UnitZ())}, law,
          contact::FrictionLaw{0.4, 0.05});
      const contact::ContactEvaluation ep = plane.evaluate(0, b.span());
      const std::array<Wrench, 2> wp = wrenches_of(plane, b);
      CHECK((wp[0].tau_Br_W - (ep.point.p_WP - b.states[0].p_WBr).cross(wp[0].f_W)).norm() <
            1e-12 * wp[0].f_W.norm());
      CHECK(wp[1].f_W.norm() == 0.0);
      CHECK(wp[1].tau_Br_W.norm() == 0.0);
    }
  }
}

TEST_CASE("separated contacts apply nothing, store nothing, dissipate nothing", "[core][contact]") {
  for (const contact::NormalLaw& law : laws()) {
    const TwoBodies b(50);
    const contact::ContactElement element(
        {penetrating_sphere_plane(b, 0.1, -1e-9, Eigen::Vector3d::UnitY()),
         sphere_pair(b, 0.2, 0.15, 1e-9)},
        law, contact::FrictionLaw{0.4, 0.05});
    const std::array<Wrench, 2> w = wrenches_of(element, b);
    for (const Wrench& x : w) {
      CHECK(x.f_W.norm() == 0.0);
      CHECK(x.tau_Br_W.norm() == 0.0);
    }
    CHECK(element.potential_energy({0.0, 0.0}, b.span()) == 0.0);
    CHECK(element.dissipated_power({0.0, 0.0}, b.span()) == 0.0);
    std::array<double, 2> g{};
    element.switching_functions({0.0, 0.0}, b.span(), g);
    // Placed at ±1e-9 from O(1) coordinates: round-off 1e-15.
    CHECK(g[0] == Approx(1e-9).margin(1e-14));
    CHECK(g[1] == Approx(1e-9).margin(1e-14));
    CHECK(element.switching_function_count() == 2);
  }
}

TEST_CASE("damping and friction oppose the relative velocity, dissipated power is their work",
          "[core][contact]") {
  int pressed = 0, released = 0;
  for (const contact::NormalLaw& law : laws()) {
    for (unsigned seed = 60; seed < 80; ++seed) {
      TwoBodies b(seed);
      const contact::ContactElement element(
          {penetrating_sphere_plane(b, 0.1, 0.02, Eigen::Vector3d(1, 2, 3)),
           sphere_pair(b, 0.2, 0.15, -0.015)},
          law, contact::FrictionLaw{0.7, 0.2});
      double power_nc = 0.0;  // power of the non-conservative loads on the bodies
      {
        const std::array<Wrench, 2> total = wrenches_of(element, b);
        TwoBodies rest = b;
        rest.set_rest();
        const std::array<Wrench, 2> elastic = wrenches_of(element, rest);
        for (std::size_t j = 0; j < 2; ++j) {
          const Eigen::Vector3d w_WB_W = b.kinematics[j].R_WB * b.states[j].w_WB_B;
          power_nc += (total[j].f_W - elastic[j].f_W).dot(b.states[j].v_WBr) +
                      (total[j].tau_Br_W - elastic[j].tau_Br_W).dot(w_WB_W);
        }
      }
      double dissipated = 0.0;
      for (int k = 0; k < 2; ++k) {
        const contact::ContactEvaluation e = element.evaluate(k, b.span());
        REQUIRE(e.normal.elastic > 0.0);
        // Friction is antiparallel to the slip: F_t·v_t = −|F_t||v_t| (1e-12 relative).
        CHECK(
            e.f_friction_W.dot(e.v_t_W) ==
            Approx(-e.f_friction_W.norm() * e.v_t_W.norm()).margin(1e-12 * e.f_friction_W.norm()));
        if (e.normal.total > 0.0) {
          CHECK(e.f_friction_W.dot(e.v_t_W) < 0.0);
          ++pressed;
        } else {
          CHECK(e.f_friction_W.norm() == 0.0);  // released by the clamp: no normal, no friction
          ++released;
        }
        // The non-conservative normal force (F − F_e) n has the sign of δ̇: it opposes the
        // normal relative velocity −δ̇.
        CHECK(e.normal.dissipative() * e.delta_dot >= 0.0);
        CHECK(e.normal.total >= 0.0);
        CHECK(e.dissipated_power() >= 0.0);
        dissipated += e.dissipated_power();
      }
      CHECK(element.dissipated_power({0.0, 0.0}, b.span()) == Approx(dissipated).epsilon(1e-14));
      CHECK(dissipated > 0.0);
      // −(Σ non-conservative force · velocity): sums of O(100 W) products, 1e-11 relative.
      CHECK(-power_nc == Approx(dissipated).epsilon(1e-11));
    }
  }
  // Both branches were exercised.
  CHECK(pressed > 20);
  CHECK(released > 5);
}

TEST_CASE("the clamp: a separating contact never pulls and still dissipates", "[core][contact]") {
  const contact::NormalLaw linear = contact::NormalLaw::linear(1e3, 50.0);
  // δ = 0.01, δ̇ = −1: k δ + c δ̇ = 10 − 50 < 0 → F = 0, F_nc = −F_e, power F_nc δ̇ = k δ|δ̇|.
  const contact::NormalForce f = linear.force(0.01, -1.0);
  CHECK(f.total == 0.0);
  CHECK(f.elastic == Approx(10.0).epsilon(1e-15));
  CHECK(f.dissipative() * -1.0 == Approx(10.0).epsilon(1e-15));
  // Hunt–Crossley with α v = 2 > 1 on the way out would pull: clamped.
  const contact::NormalLaw hc = contact::NormalLaw::hunt_crossley(1e4, 1.5, 0.2, 1.0);
  CHECK(hc.force(0.01, -2.0 / hc.alpha()).total == 0.0);
  CHECK(hc.force(-0.01, 5.0).total == 0.0);
}

/// Integrates the free impact δ̈ = acc(δ, δ̇) from δ = 0, δ̇ = v⁻ with classical RK4 at step h
/// until δ returns to 0 and returns the rebound speed over v⁻ (crossing located by linear
/// interpolation in δ within the last step).
template <class Acceleration>
double rebound_ratio(Acceleration acc, double v_in, double h, double* duration) {
  double d = 0.0, v = v_in, t = 0.0;
  for (int step = 0; step < 10'000'000; ++step) {
    const double k1d = v, k1v = acc(d, v);
    const double k2d = v + 0.5 * h * k1v, k2v = acc(d + 0.5 * h * k1d, v + 0.5 * h * k1v);
    const double k3d = v + 0.5 * h * k2v, k3v = acc(d + 0.5 * h * k2d, v + 0.5 * h * k2v);
    const double k4d = v + h * k3v, k4v = acc(d + h * k3d, v + h * k3v);
    const double d1 = d + h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
    const double v1 = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    if (d1 <= 0.0 && step > 0) {
      const double s = d / (d - d1);
      if (duration != nullptr) *duration = t + s * h;
      return -(v + s * (v1 - v)) / v_in;
    }
    d = d1;
    v = v1;
    t += h;
  }
  return NAN;
}

/// rebound_ratio of the free impact m δ̈ = −F(δ, δ̇) under `law`, at 4000 steps per
/// penetration time δ_max/v⁻.
double simulated_restitution(const contact::NormalLaw& law, double mass, double v_in,
                             double* duration) {
  const double h = law.impact_penetration(mass, v_in) / v_in / 4000.0;
  return rebound_ratio(
      [&](double d, double v) {
        // The one-sided limit δ → 0⁺ at the start (the linear law's force jumps to c v⁻ there;
        // a stage at δ = 0 would see the separated branch and cost RK4 its order on the first
        // step).
        return -law.force(std::max(d, 1e-300), v).total / mass;
      },
      v_in, h, duration);
}

TEST_CASE("Hunt–Crossley restitution: the exact relation against direct integration",
          "[core][contact]") {
  for (double e : {0.05, 0.3, 0.5, 0.8, 0.99, 0.999999}) {
    const double a = contact::hunt_crossley_alpha_times_speed(e);
    // Round trip through both root finders (48-bit tolerance): 1e-12.
    CHECK(contact::hunt_crossley_restitution(a) == Approx(e).epsilon(1e-12));
    // φ(a) = φ(−a e) in closed form (log1p; a e < 1).
    CHECK(a - std::log1p(a) == Approx(-a * e - std::log1p(-a * e)).epsilon(1e-9));
  }
  CHECK(contact::hunt_crossley_alpha_times_speed(1.0) == 0.0);
  // Light damping: α v⁻ → 3(1 − e)/2 (Hunt & Crossley 1975), error O((1 − e)²).
  CHECK(contact::hunt_crossley_alpha_times_speed(0.999) == Approx(1.5e-3).epsilon(2e-3));

  // The relation is independent of k, m and n: an impact at v_ref rebounds with e, one at
  // 2 v_ref with hunt_crossley_restitution(2 α v_ref). RK4 with t_c/~12000 steps: the error
  // near δ = 0 (F ~ δⁿ, not smooth) is well below 1e-7; crossing interpolation error
  // ~h² a/v ≈ 0 there (F → 0). 1e-6.
  struct Case {
    double k, n, e, v_ref, m;
  };
  for (const Case& c : {Case{1e5, 1.5, 0.5, 1.0, 1.0}, Case{3e4, 1.0, 0.8, 2.5, 0.2},
                        Case{2e6, 2.0, 0.2, 0.5, 7.0}}) {
    const contact::NormalLaw law = contact::NormalLaw::hunt_crossley(c.k, c.n, c.e, c.v_ref);
    CHECK(simulated_restitution(law, c.m, c.v_ref, nullptr) == Approx(c.e).epsilon(1e-6));
    const double e_fast = contact::hunt_crossley_restitution(2.0 * law.alpha() * c.v_ref);
    CHECK(e_fast < c.e);  // faster impacts lose more
    CHECK(simulated_restitution(law, c.m, 2.0 * c.v_ref, nullptr) == Approx(e_fast).epsilon(1e-6));
  }
}

TEST_CASE("linear spring-dashpot: restitution without and with the clamp", "[core][contact]") {
  // linear_from_restitution(k, e, m) picks the damping c for which the unclamped impact
  // m δ̈ + c δ̇ + k δ = 0 rebounds with e: checked by integrating that impact (RK4, not the
  // closed form e = exp(−ζπ/√(1 − ζ²)) the law is built from). With the clamp the body is
  // released when k δ + c δ̇ = 0, at ω_d t* = π − 2 asin ζ, with δ̇(t*) = −v⁻ e^{−ζω t*}:
  // e_clamp = exp(−ζ(π − 2 asin ζ)/√(1−ζ²)) (docs/contact.md), checked by the RK4 impact under
  // the law itself (after release the body flies free at constant speed, so the speed at the
  // crossing is that at release).
  //
  // Tolerance 1e-6 for both: RK4 at ω h ≈ 1/2500 (the unclamped impact's step; the law's
  // impact uses 4000 steps per penetration time, of the same order) errs by ~π (ωh)⁴ ≈ 1e-13
  // relative over the half period of the impact; the crossing found by linear interpolation
  // within the last step errs by ~(ωh)²/8 ≈ 2e-8 in the speed (δ̈ and v̈ are O(ω v⁻) and
  // O(ω² v⁻) there). 1e-6 leaves a factor 50 over that.
  for (double e : {0.2, 0.5, 0.9}) {
    const double m = 1.7, k = 4e4;
    const contact::NormalLaw law = contact::NormalLaw::linear_from_restitution(k, e, m);
    const double c = law.damping();
    const double omega = std::sqrt(k / m);
    const double unclamped = rebound_ratio([&](double d, double v) { return -(k * d + c * v) / m; },
                                           1.3, 1.0 / (2500.0 * omega), nullptr);
    CHECK(unclamped == Approx(e).epsilon(1e-6));
    const double zeta = c / (2.0 * std::sqrt(k * m));
    const double measured = simulated_restitution(law, m, 1.3, nullptr);
    CHECK(measured == Approx(contact::linear_restitution_with_clamp(zeta)).epsilon(1e-6));
    CHECK(measured > e);  // the clamp removes the pulling phase: the rebound is faster
  }
}

TEST_CASE("friction law: slip factor is continuous and saturates", "[core][contact]") {
  const contact::FrictionLaw f{0.3, 2e-3};
  // Across the series branch at x = 1e-4: relative jump below the dropped term 2x⁴/15 ~ 1e-17.
  CHECK(f.slip_factor(1e-4 * 2e-3 * (1 - 1e-12)) ==
        Approx(f.slip_factor(1e-4 * 2e-3 * (1 + 1e-12))).epsilon(1e-14));
  CHECK(f.slip_factor(0.0) == Approx(1.0 / 2e-3).epsilon(1e-15));
  // tanh(10) = 1 − 4e-9: |F_t| = μ F_n within 1e-8 at |v_t| = 10 v_reg.
  CHECK(f.slip_factor(20e-3) * 20e-3 == Approx(1.0).epsilon(1e-8));
}

TEST_CASE("contact parameters: frequency, step limit and validation", "[core][contact]") {
  const contact::ContactElement linear(
      {contact::ContactPair::point_plane(0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                         Eigen::Vector3d::UnitZ())},
      contact::NormalLaw::linear(1e4, 0.0), contact::FrictionLaw{}, 4.0);
  // √(k/m) = √(1e4/4) = 50 and 2/ω = 0.04: one or two correctly rounded operations each,
  // ≤ 2 ε = 4.4e-16 relative.
  CHECK(linear.frequency(4.0) == Approx(50.0).epsilon(1e-15));
  CHECK(linear.explicit_step_limit(4.0) == Approx(0.04).epsilon(1e-15));
  CHECK_THAT(linear.describe(), Catch::Contains("omega = 50 rad/s"));
  // Hertz at v_ref = 1, m = 1, k = 1e6: δ_max = (1.25e-6)^0.4, k_lin = 1.5e6 √δ_max.
  const contact::ContactElement hertz(
      {contact::ContactPair::point_plane(0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                         Eigen::Vector3d::UnitZ())},
      contact::NormalLaw::hunt_crossley(1e6, 1.5, 0.5, 1.0), contact::FrictionLaw{});
  CHECK(hertz.effective_stiffness(1.0) ==
        Approx(1.5e6 * std::sqrt(std::pow(1.25e-6, 0.4))).epsilon(1e-14));
  CHECK_THROWS(contact::NormalLaw::hunt_crossley(1e6, 1.5, 0.0, 1.0));
  CHECK_THROWS(contact::NormalLaw::hunt_crossley(1e6, 1.5, 1.1, 1.0));
  CHECK_THROWS(contact::NormalLaw::linear(-1.0, 0.0));
  CHECK_THROWS(contact::ContactPair::sphere_plane(
      0, Eigen::Vector3d::Zero(), 0.1, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  CHECK_THROWS(contact::ContactPair::sphere_sphere(1, Eigen::Vector3d::Zero(), 0.1, 1,
                                                   Eigen::Vector3d::Zero(), 0.1));
  CHECK_THROWS(contact::ContactElement({}, contact::NormalLaw::linear(1.0, 0.0),
                                       contact::FrictionLaw{0.3, 0.0}));
}

TEST_CASE("contact evaluation allocates nothing", "[core][contact][allocation]") {
  const TwoBodies b(90);
  const contact::ContactElement element(
      {penetrating_sphere_plane(b, 0.1, 0.02, Eigen::Vector3d::UnitZ()),
       sphere_pair(b, 0.2, 0.15, -0.015)},
      contact::NormalLaw::hunt_crossley(1e5, 1.5, 0.5, 1.0), contact::FrictionLaw{0.3, 1e-3});
  std::array<Wrench, 2> w;
  std::array<double, 2> g{};
  double sum = 0.0;
  const long n = testing::count_allocations([&] {
    element.add_wrenches({0.0, 0.0}, b.span(), w);
    element.switching_functions({0.0, 0.0}, b.span(), g);
    sum = element.potential_energy({0.0, 0.0}, b.span()) +
          element.dissipated_power({0.0, 0.0}, b.span());
  });
  CHECK(n == 0);
  CHECK(sum > 0.0);
}

TEST_CASE("one pass over the pairs gives what the separate calls give", "[core][contact]") {
  // The extended/quad references evaluate each pair once (add_wrenches_and_rates); core::Model
  // calls add_wrenches, dissipated_power, wear_samples, switching_functions and clamp_functions
  // apart. Both are the same expressions in the same order, so they agree to the last bit; a
  // separated pair (seed ≥ 10: gap > 0) contributes nothing but its gap and clamp value.
  for (const contact::NormalLaw& law : laws()) {
    int pushed = 0;
    for (unsigned seed = 1; seed <= 20; ++seed) {
      CAPTURE(seed);
      const TwoBodies b(seed);
      const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.4, 1.0).normalized();
      const double gap = 0.03 * (static_cast<double>(seed) / 10.0 - 1.0);
      const contact::ContactElement element(
          {penetrating_sphere_plane(b, 0.1, -gap, n), sphere_pair(b, 0.2, 0.15, gap)}, law,
          contact::FrictionLaw{0.4, 0.05}, 0.0, "wear");
      const LoadContext context{0.0, 0.0};
      std::array<Wrench, 2> fused;
      std::array<Wrench, 2> separate;
      const double before = 0.1;  // another element's power: added to once, after the pairs' sum
      double dissipated = before;
      std::array<WearSample, 1> wear_fused;
      std::array<WearSample, 1> wear_separate;
      std::array<double, 2> gaps_fused{};
      std::array<double, 2> gaps_separate{};
      std::array<double, 2> clamps_fused{};
      std::array<double, 2> clamps_separate{};
      element.add_wrenches_and_rates(context, b.span(), fused, &dissipated, wear_fused, gaps_fused,
                                     clamps_fused);
      element.add_wrenches(context, b.span(), separate);
      element.wear_samples(context, b.span(), wear_separate);
      element.switching_functions(context, b.span(), gaps_separate);
      element.clamp_functions(context, b.span(), clamps_separate);
      for (std::size_t i = 0; i < 2; ++i) {
        CHECK(fused[i].f_W == separate[i].f_W);
        CHECK(fused[i].tau_Br_W == separate[i].tau_Br_W);
        CHECK(fused[i].torque_magnitude == separate[i].torque_magnitude);
        CHECK(gaps_fused[i] == gaps_separate[i]);
        CHECK(clamps_fused[i] == clamps_separate[i]);
      }
      CHECK(dissipated == before + element.dissipated_power(context, b.span()));
      CHECK(wear_fused[0].normal_force == wear_separate[0].normal_force);
      CHECK(wear_fused[0].slip_speed == wear_separate[0].slip_speed);
      CHECK(wear_fused[0].wear_power == wear_separate[0].wear_power);
      if (fused[1].f_W.norm() > 0.0) ++pushed;
    }
    // Penetrating pairs moving apart may be clamped to F_n = 0; most push.
    CHECK(pushed >= 5);
  }
}

}  // namespace
}  // namespace flexref::core
