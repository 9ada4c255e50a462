#pragma once
/// \file rotation_samples.hpp
/// Rotation vectors that cover every branch of the SO(3) and Euler-parameter functions
/// (docs/design/style.md "Tests", after Sophus' and manif's testers): zero, 1e-8 about five
/// axes, both sides of and exactly at each small-angle branch switch of the function under
/// test, generic rotations from a fixed seed, and angles at and just below π (including exactly
/// π about random axes, where sign conventions are decided by round-off).
#include <Eigen/Core>
#include <initializer_list>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/floating_point.hpp"

namespace flexref::testing {

struct RotationSample {
  std::string name;
  Eigen::Vector3d phi;
};

inline Eigen::Vector3d generic_axis() { return Eigen::Vector3d(1.0, -2.0, 3.0).normalized(); }

/// The samples; `branch_angles` are the |φ| where the tested code switches to a Taylor series,
/// `seed` fixes the generic and random-axis samples.
inline std::vector<RotationSample> rotation_vector_samples(
    std::initializer_list<double> branch_angles, unsigned seed) {
  std::vector<RotationSample> samples;
  samples.push_back({"zero", Eigen::Vector3d::Zero()});
  const std::vector<Eigen::Vector3d> axes = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                             Eigen::Vector3d::UnitZ(), generic_axis(),
                                             Eigen::Vector3d(-0.48, 0.6, -0.64)};
  for (std::size_t i = 0; i < axes.size(); ++i) {
    samples.push_back({"1e-8 axis " + std::to_string(i), 1e-8 * axes[i]});
  }
  // Just below and just above each branch switch; 1e-13 relative is far above the rounding of
  // |φ| (ε) so the branch taken is certain, and far below any visible change of the functions.
  for (const double angle : branch_angles) {
    const std::string a = std::to_string(angle);
    samples.push_back({"below switch " + a, angle * (1.0 - 1e-13) * generic_axis()});
    samples.push_back({"above switch " + a, angle * (1.0 + 1e-13) * generic_axis()});
    samples.push_back({"at switch " + a, angle * Eigen::Vector3d::UnitY()});
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> angle(0.1, 3.0);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d axis =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    samples.push_back({"generic " + std::to_string(i), angle(rng) * axis});
  }
  const std::vector<std::pair<std::string, double>> near_pi = {
      {"pi - 1e-6", kPi - 1e-6}, {"pi - 1e-10", kPi - 1e-10}, {"pi", kPi}};
  for (const auto& [label, a] : near_pi) {
    for (std::size_t i = 0; i < axes.size(); ++i) {
      samples.push_back({label + " axis " + std::to_string(i), a * axes[i]});
    }
  }
  // Exactly π about random axes: for about a third of them the rounded |φ| exceeds π.
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d axis =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    samples.push_back({"pi random axis " + std::to_string(i), kPi * axis});
  }
  return samples;
}

}  // namespace flexref::testing
