#include "core/body.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/body_impl.hpp"

namespace flexref::core {

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

namespace {

void check_flexible_part(const RigidBodyDescription& d) {
  const FlexiblePart& f = *d.flexible;
  try {
    f.modal.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("body '" + d.name + "': modal data: " + e.what());
  }
  const Eigen::Index n = f.modal.mode_count();
  if ((f.q0.size() != 0 && f.q0.size() != n) || (f.qd0.size() != 0 && f.qd0.size() != n)) {
    throw std::invalid_argument("body '" + d.name + "': initial modal coordinates need " +
                                std::to_string(n) + " entries");
  }
  if (!f.q0.allFinite() || !f.qd0.allFinite()) {
    throw std::invalid_argument("body '" + d.name + "': initial modal coordinates not finite");
  }
  for (const TrackedPoint& p : d.points) {
    if (p.node >= f.modal.node_count()) {
      throw std::invalid_argument("body '" + d.name + "': point '" + p.name +
                                  "' refers to a node that does not exist");
    }
  }
  // A hub may be absent (zero mass and inertia) or a physical rigid body.
  const bool no_hub = d.mass == 0.0 && d.I_Bcm_B.isZero(0.0);
  if (!no_hub) {
    if (!(d.mass > 0.0) || !std::isfinite(d.mass)) {
      throw std::invalid_argument("body '" + d.name + "': hub mass must be positive and finite");
    }
    if (const std::string problem = inertia_problem(d.I_Bcm_B); !problem.empty()) {
      throw std::invalid_argument("body '" + d.name + "': hub " + problem);
    }
  }
}

}  // namespace

void validate_body_description(const RigidBodyDescription& d) {
  if (d.flexible) {
    check_flexible_part(d);
  } else {
    if (!(d.mass > 0.0) || !std::isfinite(d.mass)) {
      throw std::invalid_argument("body '" + d.name + "': mass must be positive and finite");
    }
    if (const std::string problem = inertia_problem(d.I_Bcm_B); !problem.empty()) {
      throw std::invalid_argument("body '" + d.name + "': " + problem);
    }
  }
  const bool vectors_finite = d.p_BoBcm_B.allFinite() && d.p_BoPivot_B.allFinite() &&
                              d.initial.p_WBo.allFinite() && d.initial.theta_WB.allFinite() &&
                              d.initial.v_WBo.allFinite() && d.initial.w_WB_B.allFinite() &&
                              d.prescribed.axis_W.allFinite();
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
    if (d.points[i].node >= 0 && !d.flexible) {
      throw std::invalid_argument("body '" + d.name + "': point '" + d.points[i].name +
                                  "' names a node but the body is rigid");
    }
  }
  if (d.motion != MotionKind::kFree && d.initial.v_WBo.squaredNorm() != 0.0) {
    throw std::invalid_argument("body '" + d.name +
                                "': the origin velocity of a pivot or prescribed body follows "
                                "from its angular velocity; give none");
  }
  if (d.motion == MotionKind::kPrescribed) {
    if (std::abs(d.prescribed.axis_W.norm() - 1.0) > 1e-12) {
      throw std::invalid_argument("body '" + d.name +
                                  "': the prescribed axis is not a unit vector");
    }
    const AngleLaw& law = d.prescribed.law;
    if (!std::isfinite(law.rate) ||
        (law.kind == AngleLaw::Kind::kSpinUp &&
         (!(law.spin_up_time > 0.0) || !std::isfinite(law.spin_up_time)))) {
      throw std::invalid_argument("body '" + d.name +
                                  "': the prescribed angle law needs a finite rate and a "
                                  "positive spin-up time");
    }
  }
  if (std::abs(d.initial.theta_WB.norm() - 1.0) > 1e-12) {
    throw std::invalid_argument("body '" + d.name + "': orientation is not a unit quaternion");
  }
}

template class BodyTpl<double>;

}  // namespace flexref::core
