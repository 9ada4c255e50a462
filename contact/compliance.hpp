#pragma once
/// \file compliance.hpp
/// How soft a body is at a point, for the frequencies of the penalty elements attached there
/// (docs/joints.md, "Frequencies and step limits"): the translational compliance (inverse
/// effective mass matrix) and the angular compliance (inverse inertia), world frame, at the
/// body's initial attitude.
#include <Eigen/Core>

#include "core/body.hpp"

namespace flexref::contact {

struct Compliance {
  Eigen::Matrix3d translational = Eigen::Matrix3d::Zero();  ///< 1/kg
  Eigen::Matrix3d angular = Eigen::Matrix3d::Zero();        ///< 1/(kg·m²)
};

/// A free body: 1/m I + r̃ᵀ J⁻¹ r̃ (r from the centre of mass); a pivot body: r̃ᵀ J_O⁻¹ r̃ (r from
/// the pivot); a prescribed body: none (zero). The angular part is J⁻¹ (about Br). Rotated to
/// world with the initial attitude. p_BoP_B is the point from the frame origin, body frame.
Compliance body_compliance(const core::Body& body, const Eigen::Vector3d& p_BoP_B);

/// 1/λ_max of a compliance matrix: the smallest effective mass or inertia over directions
/// (+∞ when nothing moves).
double smallest_effective(const Eigen::Matrix3d& compliance);

}  // namespace flexref::contact
