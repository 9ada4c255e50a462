#pragma once
/// \file exact_scenes.hpp
/// The models with an exact solution (reference/exact_solution.hpp) that the reference tests
/// run, with their spans: the torque-free body in both circulation cases and near the
/// separatrix, the symmetric heavy top, and the compound pendulum (docs/design/scenes.md).
/// Header-only.
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

}  // namespace flexref::testing
