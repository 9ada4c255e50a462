#include "tests/support/finite_difference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace flexref::testing {

Eigen::MatrixXd central_difference_jacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd jacobian(f0.size(), x.size());
  const double cbrt_eps = std::cbrt(std::numeric_limits<double>::epsilon());
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double h = cbrt_eps * std::max(1.0, std::abs(x(j)));
    Eigen::VectorXd xp = x;
    Eigen::VectorXd xm = x;
    xp(j) += h;
    xm(j) -= h;
    jacobian.col(j) = (f(xp) - f(xm)) / (xp(j) - xm(j));
  }
  return jacobian;
}

double max_relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  return (a - b).cwiseAbs().maxCoeff() / scale;
}

}  // namespace flexref::testing
