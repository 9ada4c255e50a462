#pragma once
/// \file exact_scenes.hpp
/// The models with an exact solution (reference/exact_solution.hpp) that the reference tests
/// run, with their spans: the torque-free body in both circulation cases and near the
/// separatrix, the symmetric heavy top, and the compound pendulum (docs/design/scenes.md); and
/// a driven mechanism whose drive sets its motion (driven_parallelogram_toml). Header-only.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/body.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::testing {

/// A torque-free body with principal inertia diag(inertia), attitude θ0, angular velocity W0.
inline core::Model free_body(const Eigen::Vector3d& inertia,
                             const rotation::EulerParameters& theta0, const Eigen::Vector3d& w0_B) {
  core::RigidBodyDescription d = rigid_body("body", 1.0, inertia, w0_B);
  d.initial.theta_WB = theta0;
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  return core::Model(std::move(bodies), Elements{});
}

/// pendulum (docs/design/scenes.md): m = 1, J_C = 1e-3 I, centre of mass at body (1, 0, 0),
/// pivot at the body origin, gravity, released at rest from the identity attitude (horizontal).
inline core::Model compound_pendulum() {
  const Eigen::Vector3d com(1.0, 0.0, 0.0);
  core::RigidBodyDescription d =
      rigid_body("pendulum", 1.0, {1e-3, 1e-3, 1e-3}, Eigen::Vector3d::Zero());
  d.p_BoBcm_B = com;
  d.motion = core::MotionKind::kPivot;
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  Elements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0.0, 0.0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, 1.0, com}}));
  return core::Model(std::move(bodies), std::move(elements));
}

struct ExactScene {
  std::string name;
  std::function<core::Model()> model;
  double end_time = 0.0;  ///< s
};

inline std::vector<ExactScene> exact_scenes() {
  const rotation::EulerParameters identity = rotation::identity_euler_parameters();
  const rotation::EulerParameters tilted =
      rotation::EulerParameters(0.9, 0.1, -0.3, 0.2).normalized();
  return {
      // free_spin: |π|² > 2E I_mid, the momentum circles the max-inertia axis. 100 s, the scene.
      {"free_spin (circulation about the max axis)",
       [=] {
         return free_body({3.0, 4.0, 5.0}, identity, {0.2, 0.3, 2.0});
       },
       100.0},
      // |π|² < 2E I_mid: the momentum circles the min-inertia axis; a tilted initial attitude.
      {"torque-free, circulation about the min axis",
       [=] {
         return free_body({3.0, 4.0, 5.0}, tilted, {2.0, 0.3, 0.2});
       },
       100.0},
      // 5e-3 (relative) off the book's intermediate axis: flips every ~1.6 s, errors amplified
      // ~200 per flip; 3 s (two flips).
      {"torque-free, near the separatrix",
       [=] {
         return free_body({1.0, 2.0, 2.8}, identity, {0.05, 10.0, 0.05});
       },
       3.0},
      {"heavy_top", [] { return heavy_top(); }, 2.0},
      {"pendulum", [] { return compound_pendulum(); }, 10.0},
  };
}

/// IFToMM A02 with N = 1 as a scene file's text: a parallelogram four-bar, cranks `left` and
/// `right` of 1 m (m = 1 kg) vertical at t = 0, the coupler horizontal; joint A drives the left
/// crank clockwise at 1 rad/s, so the cranks' attitude is exactly a turn of π/2 − t about +z and
/// the coupler's the identity (it translates), until the links become collinear at t = π/2 (the
/// mechanism's change point, where J M⁻¹ Jᵀ loses rank).
inline std::string driven_parallelogram_toml(const std::string& end_time) {
  std::string text =
      "[scene]\nname = \"parallelogram\"\nend_time = " + end_time + "\noutput_step = 0.01\n";
  const auto rod = [](const std::string& name, const std::string& at, bool upright) {
    // Upright: turned by π/2 about +z, θ = (cos π/4, 0, 0, sin π/4) to 17 digits.
    return "[[body]]\nname = \"" + name + "\"\nmass = 1.0\ninertia = [1e-4, 0.0833333333333, " +
           "0.0833333333333]\ncenter_of_mass = [0.5, 0.0, 0.0]\nposition = " + at +
           (upright ? "\norientation = [0.70710678118654757, 0.0, 0.0, 0.70710678118654757]\n"
                    : "\n");
  };
  text += rod("left", "[0.0, 0.0, 0.0]", true) + "angular_velocity = [0.0, 0.0, -1.0]\n";
  text += rod("coupler", "[0.0, 1.0, 0.0]", false) + "velocity = [1.0, 0.0, 0.0]\n";
  text += rod("right", "[1.0, 0.0, 0.0]", true) + "angular_velocity = [0.0, 0.0, -1.0]\n";
  const auto joint = [](const std::string& name, const std::string& a, const std::string& pa,
                        const std::string& b, const std::string& pb, const std::string& extra) {
    return "[[joint]]\nname = \"" + name +
           "\"\nmodel = \"ideal\"\nkind = \"revolute\"\nbody_a = \"" + a + "\"\npoint_a = " + pa +
           "\nbody_b = \"" + b + "\"\npoint_b = " + pb +
           "\naxis_a = [0.0, 0.0, 1.0]\naxis_b = [0.0, 0.0, 1.0]\n" + extra;
  };
  text += joint("A", "left", "[0.0, 0.0, 0.0]", "ground", "[0.0, 0.0, 0.0]",
                "drive = { law = \"constant-rate\", rate = -1.0 }\n");
  text += joint("B", "coupler", "[0.0, 0.0, 0.0]", "left", "[1.0, 0.0, 0.0]", "");
  text += joint("C", "coupler", "[1.0, 0.0, 0.0]", "right", "[1.0, 0.0, 0.0]", "");
  text += joint("D", "right", "[0.0, 0.0, 0.0]", "ground", "[1.0, 0.0, 0.0]", "");
  return text;
}

}  // namespace flexref::testing
