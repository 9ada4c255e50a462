#include "contact/bushing.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/floating_point.hpp"

namespace rotation = flexref::rotation;
namespace contact = flexref::contact;

namespace {

namespace core = flexref::core;
using Eigen::Vector3d;

using flexref::testing::kEps;

/// Two rigid bodies at arbitrary poses, with reference points Br off their frame origins (as
/// a free body's centre of mass is), and the kinematics the model would build for them.
struct Configuration {
  std::array<core::BodyState, 2> states;
  std::array<Vector3d, 2> p_BoBr_B{Vector3d(0.1, -0.2, 0.3), Vector3d(-0.3, 0.05, 0.2)};
  std::vector<core::BodyKinematics> kinematics = std::vector<core::BodyKinematics>(2);
  std::vector<core::Wrench> wrenches = std::vector<core::Wrench>(2);

  void update() {
    for (std::size_t i = 0; i < 2; ++i) {
      kinematics[i].state = &states[i];
      kinematics[i].R_WB = rotation::rotation_matrix(states[i].theta_WB);
      kinematics[i].p_BoBr_B = p_BoBr_B[i];
    }
  }
  const std::vector<core::Wrench>& evaluate(const core::ForceElement& e) {
    update();
    for (core::Wrench& w : wrenches) w.set_zero();
    e.add_wrenches({}, kinematics, wrenches);
    return wrenches;
  }
  double potential(const core::ForceElement& e) {
    update();
    return e.potential_energy({}, kinematics);
  }
  double dissipated(const core::ForceElement& e) {
    update();
    return e.dissipated_power({}, kinematics);
  }
};

Vector3d random_vector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

rotation::EulerParameters random_attitude(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return rotation::EulerParameters(n(rng), n(rng), n(rng), n(rng)).normalized();
}

Configuration random_configuration(std::mt19937& rng) {
  Configuration c;
  for (core::BodyState& s : c.states) {
    s.p_WBr = random_vector(rng, 0.5);
    s.theta_WB = random_attitude(rng);
    s.v_WBr = random_vector(rng, 1.0);
    s.w_WB_B = random_vector(rng, 2.0);
  }
  c.update();
  return c;
}

/// The four cases of every property: spherical and revolute, body–body and body–ground.
/// Points are from the frame origins; the ground end's point and axis are world data.
struct Case {
  const char* name;
  bool revolute;
  bool ground;
};
constexpr std::array<Case, 4> kCases{{{"spherical body-body", false, false},
                                      {"spherical body-ground", false, true},
                                      {"revolute body-body", true, false},
                                      {"revolute body-ground", true, true}}};

std::unique_ptr<core::ForceElement> make_bushing(const Case& c,
                                                 const contact::BushingParameters& p) {
  const contact::BushingEnd a{0, Vector3d(0.4, 0.1, -0.2), Vector3d(0.2, 1.0, 0.1)};
  const contact::BushingEnd b{c.ground ? contact::kGround : 1,
                              c.ground ? Vector3d(0.3, -0.2, 0.1) : Vector3d(-0.1, 0.3, 0.25),
                              Vector3d(-0.1, 0.9, 0.3)};
  if (c.revolute) return std::make_unique<contact::RevoluteBushing>(a, b, p);
  return std::make_unique<contact::SphericalBushing>(a, b, p);
}

/// k = 2000 N/m, k_θ = 300 N·m/rad: forces O(k·|d|) ≈ 1e3 N at separations O(0.5 m).
contact::BushingParameters springs_only() {
  contact::BushingParameters p;
  p.stiffness = 2000.0;
  p.angular_stiffness = 300.0;
  return p;
}

contact::BushingParameters dampers_only() {
  contact::BushingParameters p;
  p.stiffness = 0.0;
  p.angular_stiffness = 0.0;
  p.damping = 40.0;
  p.angular_damping = 7.0;
  return p;
}

TEST_CASE("Bushing forces and torques are minus the gradient of the potential") {
  std::mt19937 rng(20240611);
  for (const Case& c : kCases) {
    SECTION(c.name) {
      const auto bushing = make_bushing(c, springs_only());
      const int bodies = c.ground ? 1 : 2;
      for (int sample = 0; sample < 10; ++sample) {
        Configuration cfg = random_configuration(rng);
        const std::vector<core::Wrench> wrenches = cfg.evaluate(*bushing);
        // Central differences at h = 1e-5 (≈ ε^(1/3), the step that balances the O(h² V''')
        // truncation against the O(ε V/h) rounding): V''' = O(k) ≈ 2e3 gives 2e-7 N, rounding
        // ε·V/h with V ≤ 1e3 J gives 2e-8 N; 1e-6 relative to the 1e3 N scale covers both.
        const double h = 1e-5;
        for (int i = 0; i < bodies; ++i) {
          core::BodyState& s = cfg.states[static_cast<std::size_t>(i)];
          const core::BodyState saved = s;
          Vector3d f_fd;
          Vector3d tau_fd;
          for (int j = 0; j < 3; ++j) {
            const Vector3d e = h * Vector3d::Unit(j);
            s.p_WBr = saved.p_WBr + e;
            const double v_plus = cfg.potential(*bushing);
            s.p_WBr = saved.p_WBr - e;
            const double v_minus = cfg.potential(*bushing);
            s.p_WBr = saved.p_WBr;
            f_fd[j] = -(v_plus - v_minus) / (2.0 * h);
            // A rotation about Br by φ in the world frame: θ ← exp(φ) ⊗ θ, A ← exp(φ̃) A.
            s.theta_WB = rotation::quaternion_multiply(rotation::exp_quaternion(e), saved.theta_WB);
            const double w_plus = cfg.potential(*bushing);
            s.theta_WB =
                rotation::quaternion_multiply(rotation::exp_quaternion(-e), saved.theta_WB);
            const double w_minus = cfg.potential(*bushing);
            s.theta_WB = saved.theta_WB;
            tau_fd[j] = -(w_plus - w_minus) / (2.0 * h);
          }
          const core::Wrench& w = wrenches[static_cast<std::size_t>(i)];
          INFO("body " << i << " f " << w.f_W.transpose() << " fd " << f_fd.transpose());
          INFO("tau " << w.tau_Br_W.transpose() << " fd " << tau_fd.transpose());
          CHECK((w.f_W - f_fd).norm() <= 1e-6 * 1e3);
          CHECK((w.tau_Br_W - tau_fd).norm() <= 1e-6 * 1e3);
        }
      }
    }
  }
}

TEST_CASE("Body-body bushings obey the strong form of Newton's third law") {
  // With springs and dampers: the forces are opposite and act at one point (the midpoint), the
  // couples are opposite, so the resultant force and moment about the origin vanish.
  std::mt19937 rng(7);
  contact::BushingParameters p = springs_only();
  p.damping = 40.0;
  p.angular_damping = 7.0;
  for (const Case& c : {kCases[0], kCases[2]}) {
    SECTION(c.name) {
      const auto bushing = make_bushing(c, p);
      for (int sample = 0; sample < 10; ++sample) {
        Configuration cfg = random_configuration(rng);
        const std::vector<core::Wrench>& w = cfg.evaluate(*bushing);
        const Vector3d force = w[0].f_W + w[1].f_W;
        const Vector3d moment = w[0].tau_Br_W + cfg.states[0].p_WBr.cross(w[0].f_W) +
                                w[1].tau_Br_W + cfg.states[1].p_WBr.cross(w[1].f_W);
        // Forces O(1e3 N), arms O(1 m): rounding of a few ε times that.
        const double scale = w[0].f_W.norm() + w[0].tau_Br_W.norm();
        INFO("force " << force.transpose() << " moment " << moment.transpose());
        CHECK(force.norm() <= 50.0 * kEps * scale);
        CHECK(moment.norm() <= 50.0 * kEps * scale);
      }
    }
  }
}

TEST_CASE("Bushings apply no load at the assembled configuration") {
  // B is placed so that Q coincides with P and a_B with a_A, then turned by an arbitrary
  // angle about the hinge (free rotation); both bodies move as one rigid body (same ω, and
  // v_B(Q) = v_A(P)), so the dampers see no relative motion either.
  std::mt19937 rng(99);
  contact::BushingParameters p = springs_only();
  p.damping = 40.0;
  p.angular_damping = 7.0;
  for (const Case& c : kCases) {
    SECTION(c.name) {
      const auto bushing = make_bushing(c, p);
      const contact::BushingEnd a{0, Vector3d(0.4, 0.1, -0.2),
                                  Vector3d(0.2, 1.0, 0.1).normalized()};
      const Vector3d a_B = Vector3d(-0.1, 0.9, 0.3).normalized();
      for (int sample = 0; sample < 5; ++sample) {
        Configuration cfg = random_configuration(rng);
        core::BodyState& sa = cfg.states[0];
        core::BodyState& sb = cfg.states[1];
        const Eigen::Matrix3d R_A = rotation::rotation_matrix(sa.theta_WB);
        const Vector3d p_WP = sa.p_WBr + R_A * (a.point - cfg.p_BoBr_B[0]);
        const Vector3d axis_W = R_A * a.axis;
        if (c.ground) {
          // The ground end of make_bushing: the world point (0.3, −0.2, 0.1) and axis a_B.
          // Move and turn A so that P lands there and a_A along a_B (a hinge angle about it).
          const Eigen::Matrix3d align =
              rotation::exp_so3(std::uniform_real_distribution<double>(-3, 3)(rng) * a_B) *
              Eigen::Quaterniond::FromTwoVectors(axis_W, a_B).toRotationMatrix();
          sa.theta_WB = rotation::euler_parameters_from_matrix(align * R_A);
          const Eigen::Matrix3d R = rotation::rotation_matrix(sa.theta_WB);
          sa.p_WBr = Vector3d(0.3, -0.2, 0.1) - R * (a.point - cfg.p_BoBr_B[0]);
          sa.v_WBr.setZero();
          sa.w_WB_B.setZero();
        } else {
          const Eigen::Matrix3d R_B =
              rotation::exp_so3(std::uniform_real_distribution<double>(-3, 3)(rng) * axis_W) *
              Eigen::Quaterniond::FromTwoVectors(a_B, axis_W).toRotationMatrix();
          sb.theta_WB = rotation::euler_parameters_from_matrix(R_B);
          const Eigen::Matrix3d R = rotation::rotation_matrix(sb.theta_WB);
          const Vector3d q(-0.1, 0.3, 0.25);
          sb.p_WBr = p_WP - R * (q - cfg.p_BoBr_B[1]);
          // Rigid co-motion: ω_B = ω_A, v_B(Br) = v_A(P) + ω × (p_WBr,B − p_WP).
          const Vector3d w_W = R_A * sa.w_WB_B;
          sb.w_WB_B = R.transpose() * w_W;
          const Vector3d v_P = sa.v_WBr + w_W.cross(p_WP - sa.p_WBr);
          sb.v_WBr = v_P + w_W.cross(sb.p_WBr - p_WP);
        }
        const std::vector<core::Wrench>& w = cfg.evaluate(*bushing);
        // Rounding of positions O(1) m times k = 2e3 N/m, axes O(1) times k_θ = 300 N·m/rad,
        // velocities O(1) times c: a few hundred ε N.
        for (int i = 0; i < (c.ground ? 1 : 2); ++i) {
          INFO("body " << i << " f " << w[static_cast<std::size_t>(i)].f_W.transpose() << " tau "
                       << w[static_cast<std::size_t>(i)].tau_Br_W.transpose());
          CHECK(w[static_cast<std::size_t>(i)].f_W.norm() <= 1e4 * kEps * 2e3);
          CHECK(w[static_cast<std::size_t>(i)].tau_Br_W.norm() <= 1e4 * kEps * 2e3);
        }
        CHECK(cfg.potential(*bushing) <= 1e-20);
        CHECK(cfg.dissipated(*bushing) <= 1e-20);
      }
    }
  }
}

TEST_CASE("Bushing dampers oppose the relative velocity and dissipate their power") {
  std::mt19937 rng(31);
  for (const Case& c : kCases) {
    SECTION(c.name) {
      const auto bushing = make_bushing(c, dampers_only());
      REQUIRE(bushing->depends_on_velocity());
      for (int sample = 0; sample < 10; ++sample) {
        Configuration cfg = random_configuration(rng);
        const std::vector<core::Wrench>& w = cfg.evaluate(*bushing);
        // Power of the damping loads: Σ f·v_Br + τ·ω over the bodies (the ground does not
        // move); the element reports −power as dissipated.
        double power = 0.0;
        for (int i = 0; i < (c.ground ? 1 : 2); ++i) {
          const auto k = static_cast<std::size_t>(i);
          power += w[k].f_W.dot(cfg.states[k].v_WBr) +
                   w[k].tau_Br_W.dot(cfg.kinematics[k].R_WB * cfg.states[k].w_WB_B);
        }
        const double dissipated = cfg.dissipated(*bushing);
        INFO("power " << power << " dissipated " << dissipated);
        CHECK(dissipated > 0.0);
        // Sums of O(1e2) W terms: rounding of 100 ε relative.
        CHECK(std::abs(power + dissipated) <= 100.0 * kEps * (1.0 + dissipated));
        // Body A is dragged along with the other end: its force opposes its velocity relative
        // to B at the shared point (both ends' material points at the same place), and its
        // damping couple opposes its relative angular velocity.
        const Vector3d w_A = cfg.kinematics[0].R_WB * cfg.states[0].w_WB_B;
        const Vector3d w_B =
            c.ground ? Vector3d::Zero() : Vector3d(cfg.kinematics[1].R_WB * cfg.states[1].w_WB_B);
        const Vector3d p_WP = cfg.kinematics[0].p_WP(Vector3d(0.4, 0.1, -0.2));
        const Vector3d p_WQ =
            c.ground ? Vector3d(0.3, -0.2, 0.1) : cfg.kinematics[1].p_WP(Vector3d(-0.1, 0.3, 0.25));
        const Vector3d p_WM = 0.5 * (p_WP + p_WQ);
        const Vector3d v_A = cfg.states[0].v_WBr + w_A.cross(p_WM - cfg.states[0].p_WBr);
        const Vector3d v_B =
            c.ground ? Vector3d::Zero()
                     : Vector3d(cfg.states[1].v_WBr + w_B.cross(p_WM - cfg.states[1].p_WBr));
        CHECK(w[0].f_W.dot(v_A - v_B) < 0.0);
        if (c.revolute) {
          const Vector3d couple = w[0].tau_Br_W - (p_WM - cfg.states[0].p_WBr).cross(w[0].f_W);
          CHECK(couple.dot(w_A - w_B) <= 0.0);
        }
      }
    }
  }
}

TEST_CASE("Bushing evaluation allocates nothing") {
  std::mt19937 rng(5);
  contact::BushingParameters p = springs_only();
  p.damping = 40.0;
  p.angular_damping = 7.0;
  for (const Case& c : kCases) {
    const auto bushing = make_bushing(c, p);
    Configuration cfg = random_configuration(rng);
    double sink = 0.0;
    const long n = flexref::testing::count_allocations([&] {
      bushing->add_wrenches({}, cfg.kinematics, cfg.wrenches);
      sink += bushing->potential_energy({}, cfg.kinematics);
      sink += bushing->dissipated_power({}, cfg.kinematics);
    });
    INFO(c.name);
    CHECK(n == 0);
    CHECK(std::isfinite(sink));
  }
}

TEST_CASE("Bushing parameters, validation and description") {
  const contact::BushingEnd a{0, Vector3d::Zero(), Vector3d(0, 2, 0)};
  const contact::BushingEnd ground{contact::kGround, Vector3d(1, 2, 3), Vector3d(0, 0, 3)};
  const contact::BushingParameters defaults;
  const contact::RevoluteBushing revolute(a, ground, defaults);
  CHECK(revolute.translational_stiffness() == 1e6);
  CHECK(revolute.angular_stiffness() == 1e4);
  // (0, 2, 0) and (0, 0, 3) divided by their norms, which are exact: the unit axes exactly.
  CHECK(revolute.end_a().axis == Vector3d::UnitY());
  CHECK(revolute.end_b().axis == Vector3d::UnitZ());
  CHECK_FALSE(revolute.depends_on_velocity());
  CHECK(revolute.max_body_index() == 0);
  // Without the model's bodies, a body is named by its [[body]] table, counted from 1.
  CHECK(revolute.describe().find("revolute bushing: body[1]") == 0);
  CHECK(revolute.describe().find("ground point (1, 2, 3)") != std::string::npos);

  const contact::SphericalBushing spherical(a, contact::BushingEnd{3, Vector3d::Zero()}, defaults);
  CHECK(spherical.max_body_index() == 3);
  CHECK(spherical.angular_stiffness() == 0.0);
  CHECK(spherical.describe().find("k = 1e+06 N/m") != std::string::npos);

  // The two kinds of the one bushing class: the whole descriptions, and a spherical bushing
  // given angular damping (a scene's revolute defaults) keeps none of it.
  CHECK(revolute.describe() ==
        "revolute bushing: body[1] point (0, 0, 0) to ground point (1, 2, 3), hinge axis (0, 1, 0) "
        "/ world (0, 0, 1), k = 1e+06 N/m, c = 0 N·s/m, k_theta = 10000 N·m/rad, c_theta = 0 "
        "N·m·s/rad");
  CHECK(
      spherical.describe() ==
      "spherical bushing: body[1] point (0, 0, 0) to body[4] point (0, 0, 0), k = 1e+06 N/m, c = 0 "
      "N·s/m");
  contact::BushingParameters angular_only;
  angular_only.angular_damping = 5.0;
  const contact::SphericalBushing undamped(a, ground, angular_only);
  CHECK_FALSE(undamped.depends_on_velocity());
  CHECK(undamped.parameters().angular_damping == 0.0);
  CHECK(contact::RevoluteBushing(a, ground, angular_only).depends_on_velocity());

  // ω = √(k/m), the undamped leapfrog limit 2/ω, and a damped limit below it.
  // Tolerance: √(k/m) and 2/ω (and the damped factor √2 − 1): a few roundings of O(1)-relative
  // operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
  CHECK(contact::bushing_frequency(1e6, 1.0) == Approx(1e3).epsilon(1e-14));
  CHECK(contact::bushing_stable_step(1e6, 0.0, 1.0) == Approx(2e-3).epsilon(1e-14));
  CHECK(contact::bushing_stable_step(1e6, 2e3, 1.0) ==
        Approx(2e-3 * (std::sqrt(2.0) - 1.0)).epsilon(1e-14));
  CHECK(std::isinf(contact::bushing_stable_step(0.0, 0.0, 1.0)));

  contact::BushingParameters negative;
  negative.damping = -1.0;
  CHECK_THROWS_AS(contact::SphericalBushing(a, ground, negative), std::invalid_argument);
  CHECK_THROWS_AS(contact::SphericalBushing(ground, a, defaults), std::invalid_argument);
  CHECK_THROWS_AS(contact::SphericalBushing(a, a, defaults), std::invalid_argument);
  CHECK_THROWS_AS(contact::RevoluteBushing(
                      a, contact::BushingEnd{1, Vector3d::Zero(), Vector3d::Zero()}, defaults),
                  std::invalid_argument);
}

}  // namespace
