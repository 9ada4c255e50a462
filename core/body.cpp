#include "core/body.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <utility>

namespace flexref::core {

Eigen::Matrix3d shift_inertia_from_com(const Eigen::Matrix3d& I_cm, double mass,
                                       const Eigen::Vector3d& d) {
  return I_cm + mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
}

std::string inertia_problem(const Eigen::Matrix3d& inertia) {
  if (!inertia.allFinite()) return "inertia has a non-finite entry";
  const double scale = inertia.cwiseAbs().maxCoeff();
  // Symmetry to a few ulp of the largest entry: the file gives decimal numbers, so a table
  // typed symmetric is symmetric exactly; anything larger is a typing error.
  if ((inertia - inertia.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale) {
    return "inertia tensor is not symmetric";
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  const Eigen::Vector3d j = eig.eigenvalues();
  if (!(j.minCoeff() > 0.0)) return "inertia tensor is not positive definite";
  // Triangle inequality with a relative slack of 1e-12 so that a flat disk (J3 = J1 + J2
  // exactly, written in decimal) is accepted.
  const double slack = 1e-12 * j.maxCoeff();
  if (j(0) + j(1) < j(2) - slack) {
    return "principal inertias violate the triangle inequality J1 + J2 >= J3";
  }
  return {};
}

Body::Body(RigidBodyDescription description) : description_(std::move(description)) {
  const auto& d = description_;
  if (!(d.mass > 0.0) || !std::isfinite(d.mass)) {
    throw std::invalid_argument("body '" + d.name + "': mass must be positive and finite");
  }
  if (const std::string problem = inertia_problem(d.I_Bcm_B); !problem.empty()) {
    throw std::invalid_argument("body '" + d.name + "': " + problem);
  }
  const bool vectors_finite = d.p_BoBcm_B.allFinite() && d.p_BoPivot_B.allFinite() &&
                              d.initial.p_WBo.allFinite() && d.initial.theta_WB.allFinite() &&
                              d.initial.v_WBo.allFinite() && d.initial.w_WB_B.allFinite();
  if (!vectors_finite) {
    throw std::invalid_argument("body '" + d.name +
                                "': a position, attitude or velocity is not finite");
  }
  for (std::size_t i = 0; i < d.points.size(); ++i) {
    if (!d.points[i].p_BoP_B.allFinite()) {
      throw std::invalid_argument("body '" + d.name + "': point '" + d.points[i].name +
                                  "' is not finite");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (d.points[j].name == d.points[i].name) {
        throw std::invalid_argument("body '" + d.name + "': duplicate point name '" +
                                    d.points[i].name + "'");
      }
    }
  }
  if (d.motion == MotionKind::kPivot && d.initial.v_WBo.squaredNorm() != 0.0) {
    throw std::invalid_argument("body '" + d.name +
                                "': a pivot body's origin velocity follows from its angular "
                                "velocity; give none");
  }
  if (std::abs(d.initial.theta_WB.norm() - 1.0) > 1e-12) {
    throw std::invalid_argument("body '" + d.name + "': orientation is not a unit quaternion");
  }
  const Eigen::Matrix3d I_sym = 0.5 * (d.I_Bcm_B + d.I_Bcm_B.transpose());
  if (d.motion == MotionKind::kFree) {
    p_BoBr_B_ = d.p_BoBcm_B;
    p_BrBcm_B_.setZero();
    I_Br_B_ = I_sym;
  } else {
    p_BoBr_B_ = d.p_BoPivot_B;
    p_BrBcm_B_ = d.p_BoBcm_B - d.p_BoPivot_B;
    I_Br_B_ = shift_inertia_from_com(I_sym, d.mass, p_BrBcm_B_);
  }
  I_Br_B_inverse_ = I_Br_B_.inverse();
  if (!I_Br_B_.allFinite() || !I_Br_B_inverse_.allFinite() || !std::isfinite(1.0 / d.mass)) {
    throw InertiaRangeError("body '" + d.name +
                            "': mass or inertia out of the representable range");
  }
}

}  // namespace flexref::core
