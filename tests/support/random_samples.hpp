#pragma once
/// \file random_samples.hpp
/// Random test data from a caller's fixed-seed generator (never a seed from the clock).
#include <Eigen/Core>
#include <random>

namespace flexref::testing {

/// n independent normal draws of standard deviation `size`, taken from rng in index order (a
/// fresh std::normal_distribution per call, so the draws depend only on rng's state).
inline Eigen::VectorXd random_vector(Eigen::Index n, std::mt19937& rng, double size) {
  std::normal_distribution<double> normal;
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x(i) = size * normal(rng);
  return x;
}

}  // namespace flexref::testing
