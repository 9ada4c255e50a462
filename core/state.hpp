#pragma once
/// \file state.hpp
/// The state every integrator advances, body by body, in the quasi-velocity variables of
/// design/model.md: position of the reference point Br (world), Euler parameters θ (B → W),
/// velocity of Br (world) and body-frame angular velocity ω̄ = w_WB_B. A pivot body keeps
/// p_WBr fixed and v_WBr = 0.
#include <Eigen/Core>
#include <vector>

#include "core/euler_parameters.hpp"

namespace flexref::core {

struct BodyState {
  Eigen::Vector3d p_WBr = Eigen::Vector3d::Zero();
  EulerParameters theta_WB = identity_euler_parameters();
  Eigen::Vector3d v_WBr = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_B = Eigen::Vector3d::Zero();
};

using State = std::vector<BodyState>;

/// Accelerations of one body: of Br (world) and the body-frame angular acceleration α̅.
struct BodyAcceleration {
  Eigen::Vector3d a_WBr = Eigen::Vector3d::Zero();
  Eigen::Vector3d alpha_WB_B = Eigen::Vector3d::Zero();
};

using Accelerations = std::vector<BodyAcceleration>;

/// States at output times, as every integrator returns them.
struct Trajectory {
  std::vector<double> times;
  std::vector<State> states;
};

}  // namespace flexref::core
