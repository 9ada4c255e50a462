#pragma once
/// \file finite_difference.hpp
/// Central finite differences for derivative checks in tests. The step h = ε^(1/3)·max(1,|x|)
/// balances the O(h²) truncation error against the O(ε/h) round-off, so a correct analytic
/// derivative agrees to about ε^(2/3) ≈ 4e-11 relative (times the size of the third
/// derivative); tests compare with 1e-7 to leave room for that constant.
#include <Eigen/Core>
#include <functional>

namespace flexref::testing {

/// Jacobian ∂f/∂x (rows: outputs, columns: inputs) by central differences.
Eigen::MatrixXd central_difference_jacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x);

/// Largest absolute entry of a − b, relative to max(1, largest entry of b).
double max_relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace flexref::testing
