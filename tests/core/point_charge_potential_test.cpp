#include "core/point_charge_potential.hpp"

#include <catch2/catch.hpp>

#include "core/gravity.hpp"
#include "tests/support/finite_difference.hpp"

namespace flexref::core {
namespace {

TEST_CASE("point-charge force is minus the gradient of its potential", "[core]") {
  const PointChargePotential potential(4.0, 0.3, Eigen::Vector3d(0, 0, -1), {});
  // Central differences (see finite_difference.hpp): agreement to ~1e-10 relative; forces
  // here are O(1), so 1e-7 leaves three decades.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(0.5, -0.3, 0.2),
                                   Eigen::Vector3d(2, 1, 3)}) {
    const Eigen::MatrixXd grad = testing::central_difference_jacobian(
        [&](const Eigen::VectorXd& x) {
          return Eigen::VectorXd::Constant(1, potential.unit_potential(x));
        },
        p);
    const Eigen::Vector3d force = potential.unit_force_W(p);
    CHECK(testing::max_relative_difference(-grad.transpose(), force) < 1e-7);
  }
  // Directions: attracted toward M = (0,0,−1) and repelled up from the wall z = 0.
  const Eigen::Vector3d above = potential.unit_force_W(Eigen::Vector3d(1.0, 0, 0.5));
  CHECK(above.x() < 0.0);
  const PointChargePotential wall_only(0.0, 0.3, Eigen::Vector3d(0, 0, -1), {});
  CHECK(wall_only.unit_force_W(Eigen::Vector3d(0, 0, 0.1)).z() > 0.0);
}

TEST_CASE("gravity potential decreases along g", "[core]") {
  BodyState s;
  s.p_WBr = Eigen::Vector3d(0, 0, 2);
  BodyKinematics k;
  k.state = &s;
  const UniformGravity gravity(Eigen::Vector3d(0, 0, -9.81), {{0, 2.0, Eigen::Vector3d::Zero()}});
  std::vector<BodyKinematics> bodies{k};
  // V = −m g·r = −2·(−9.81)·2 = 39.24 J, exactly representable steps.
  CHECK(gravity.potential_energy({0, 0}, bodies) == Approx(39.24).epsilon(1e-15));
}

}  // namespace
}  // namespace flexref::core
