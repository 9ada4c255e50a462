#pragma once
/// \file test_models.hpp
/// Small models built in code for the core tests: a free body under the point-charge
/// potential (the coulomb_wall scene of docs/design/scenes.md), a pivot body under gravity (the
/// heavy top of Brüls & Cardona 2010), and a loaded free body with an off-centre frame origin.
#include <memory>
#include <vector>

#include "core/applied_load.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "core/point_charge_potential.hpp"

namespace flexref::testing {

/// coulomb_wall: m = 1, J = diag(0.4, 0.9, 1.1), charges at (±0.5, 0, 0) weights 1.0 / 0.6,
/// α = 4, β = 0.3, M = (0, 0, −1), x(0) = (0, 0, 1), v(0) = (0.8, 0, 0), W0 = (0.2, 0.3, 1.5).
inline core::Model coulomb_wall_model() {
  core::RigidBodyDescription d;
  d.name = "body";
  d.mass = 1.0;
  d.I_Bcm_B = Eigen::Vector3d(0.4, 0.9, 1.1).asDiagonal();
  d.initial.p_WBo = Eigen::Vector3d(0, 0, 1);
  d.initial.v_WBo = Eigen::Vector3d(0.8, 0, 0);
  d.initial.w_WB_B = Eigen::Vector3d(0.2, 0.3, 1.5);
  std::vector<core::Body> bodies{core::Body(d)};
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::make_unique<core::PointChargePotential>(
      4.0, 0.3, Eigen::Vector3d(0, 0, -1),
      std::vector<core::PointChargePotential::Charge>{{0, Eigen::Vector3d(0.5, 0, 0), 1.0},
                                                      {0, Eigen::Vector3d(-0.5, 0, 0), 0.6}}));
  return core::Model(std::move(bodies), std::move(elements));
}

/// heavy top: pivot at the body origin, m = 15, J_C = diag(0.234375, 0.46875, 0.234375),
/// centre of mass (0, 1, 0), g = (0, 0, −9.81), W0 = (0, 150, −4.61538).
inline core::Model heavy_top_model() {
  core::RigidBodyDescription d;
  d.name = "top";
  d.mass = 15.0;
  d.p_BoBcm_B = Eigen::Vector3d(0, 1, 0);
  d.I_Bcm_B = Eigen::Vector3d(0.234375, 0.46875, 0.234375).asDiagonal();
  d.motion = core::MotionKind::kPivot;
  d.initial.w_WB_B = Eigen::Vector3d(0, 150, -4.61538);
  std::vector<core::Body> bodies{core::Body(d)};
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0, 0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, 15.0, d.p_BoBcm_B}}));
  return core::Model(std::move(bodies), std::move(elements));
}

/// A free body whose frame origin is off its centre of mass, with a full inertia tensor,
/// gravity, a body-frame force at a point and a world torque pulse.
inline core::Model loaded_free_body_model() {
  core::RigidBodyDescription d;
  d.name = "block";
  d.mass = 2.5;
  d.p_BoBcm_B = Eigen::Vector3d(0.1, -0.2, 0.3);
  Eigen::Matrix3d inertia;
  inertia << 1.0, 0.1, -0.05, 0.1, 1.5, 0.2, -0.05, 0.2, 2.0;
  d.I_Bcm_B = inertia;
  d.initial.p_WBo = Eigen::Vector3d(0.3, 0.2, 0.1);
  d.initial.theta_WB = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
  d.initial.v_WBo = Eigen::Vector3d(0.5, -1.0, 0.2);
  d.initial.w_WB_B = Eigen::Vector3d(1.0, -2.0, 3.0);
  std::vector<core::Body> bodies{core::Body(d)};
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0, 0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, d.mass, d.p_BoBcm_B}}));
  elements.push_back(std::make_unique<core::AppliedForce>(
      0, Eigen::Vector3d(1.0, 2.0, -0.5), core::LoadFrame::kBody, Eigen::Vector3d(1, 0, 0),
      core::TimeProfile::constant()));
  elements.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(0.2, 0.0, 0.2), core::LoadFrame::kWorld,
      core::TimeProfile::sin2_pulse(0.0, 0.1)));
  return core::Model(std::move(bodies), std::move(elements));
}

}  // namespace flexref::testing
