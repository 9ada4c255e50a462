#include "contact/compliance.hpp"

#include <Eigen/Eigenvalues>
#include <limits>

#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"

namespace flexref::contact {

Compliance body_compliance(const core::Body& body, const Eigen::Vector3d& p_BoP_B) {
  Compliance c;
  if (body.is_prescribed()) return c;
  const Eigen::Matrix3d& J_inv = body.I_Br_B_inverse();
  const Eigen::Matrix3d r_tilde = rotation::hat(body.p_BrP_B(p_BoP_B));
  Eigen::Matrix3d t = r_tilde.transpose() * J_inv * r_tilde;
  if (body.is_free()) t += Eigen::Matrix3d::Identity() / body.mass();
  const Eigen::Matrix3d A = rotation::rotation_matrix(body.description().initial.theta_WB);
  c.translational = A * t * A.transpose();
  c.angular = A * J_inv * A.transpose();
  return c;
}

double smallest_effective(const Eigen::Matrix3d& compliance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 *
                                                           (compliance + compliance.transpose()));
  const double lambda = eig.eigenvalues().maxCoeff();
  return lambda > 0.0 ? 1.0 / lambda : std::numeric_limits<double>::infinity();
}

}  // namespace flexref::contact
