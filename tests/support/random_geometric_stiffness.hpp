#pragma once

/// \file random_geometric_stiffness.hpp
/// Random data for tests of geometric stiffening (flexible/geometric_stiffness.hpp): normal
/// vectors and twelve dense symmetric unit-load matrices, so that every stiffening term enters.

#include <Eigen/Core>
#include <random>

#include "flexible/geometric_stiffness.hpp"
#include "tests/support/random_samples.hpp"

namespace flexref::testing {

/// E_x, E_y, E_z, then F_xx … F_zz: each the symmetric part of an n×n N(0, 1) matrix.
inline flexible::GeometricStiffness random_geometric_stiffness(Eigen::Index n, std::mt19937& rng) {
  const auto symmetric = [&] {
    const Eigen::MatrixXd A = Eigen::MatrixXd(random_vector(n * n, rng, 1.0).reshaped(n, n));
    return Eigen::MatrixXd(0.5 * (A + A.transpose()));
  };
  flexible::GeometricStiffness g;
  for (auto& M : g.E) M = symmetric();
  for (auto& M : g.F) M = symmetric();
  return g;
}

}  // namespace flexref::testing
