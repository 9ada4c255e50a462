#pragma once
/// \file matrix_checks.hpp
/// Comparison helpers that print both values on failure (docs/design/style.md "Tests"), and the
/// 3×3 ↔ 9-vector reshapes that finite-difference Jacobians of matrix-valued functions need.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <iomanip>

#include "tests/support/finite_difference.hpp"

namespace flexref::testing {

/// Checks max|actual − expected| ≤ tolerance · max(1, max|expected|) and prints both on failure.
inline void check_close(const Eigen::MatrixXd& actual, const Eigen::MatrixXd& expected,
                        double tolerance) {
  const double difference = max_relative_difference(actual, expected);
  INFO(std::setprecision(17) << "actual:\n"
                             << actual << "\nexpected:\n"
                             << expected << "\nrelative difference " << difference << ", tolerance "
                             << tolerance);
  CHECK(difference <= tolerance);
}

/// Checks |actual − expected| ≤ tolerance (absolute) and prints both on failure.
inline void check_close(double actual, double expected, double tolerance) {
  INFO(std::setprecision(17) << "actual " << actual << ", expected " << expected << ", difference "
                             << actual - expected << ", tolerance " << tolerance);
  CHECK(std::abs(actual - expected) <= tolerance);
}

/// The 9 entries of m, column by column.
inline Eigen::VectorXd flatten(const Eigen::Matrix3d& m) {
  return Eigen::Map<const Eigen::VectorXd>(m.data(), 9);
}

/// The 3×3 matrix whose columns are v's entries 0–2, 3–5, 6–8 (flatten's inverse).
inline Eigen::Matrix3d unflatten(const Eigen::VectorXd& v) {
  return Eigen::Map<const Eigen::Matrix3d>(v.data());
}

}  // namespace flexref::testing
