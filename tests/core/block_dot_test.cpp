/// \file block_dot_test.cpp
/// core/block_dot_tpl.hpp: the 6-wide dot written out is Eigen's run-time-sized dot, bit for bit
/// where Eigen packs two doubles (x86-64's SSE2, the Release build), so that the joints' solve
/// kept its results when it took it; and the general case is Eigen's own.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "core/block_dot_tpl.hpp"

namespace flexref::core {
namespace {

TEST_CASE("block_dot: Eigen's run-time-sized dot of the same blocks", "[core][joints]") {
  std::mt19937 random(52);
  std::normal_distribution<double> normal;
  // Magnitudes over twelve decades, so that the order of the sum shows in the last bits.
  Eigen::VectorXd x(64), y(64);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x(i) = normal(random) * std::exp(3.0 * normal(random));
    y(i) = normal(random) * std::exp(3.0 * normal(random));
  }
  // Eigen's dot of two doubles per packet: the 6-wide dot's sums are the same, in the same order.
  constexpr bool two_per_packet = Eigen::internal::packet_traits<double>::size == 2;
  int differing = 0;
  for (int width : {1, 3, 6, 7, 12}) {
    for (int a = 0; a + width <= 64; a += 5) {
      for (int b = 0; b + width <= 64; b += 7) {
        const double eigen = x.segment(a, width).dot(y.segment(b, width));
        const double ours = block_dot<double>(x.data() + a, y.data() + b, width);
        if (width != 6 || two_per_packet) {
          differing += ours != eigen;
        } else {
          // Other packet widths sum in another order. Either order's error is at most 6 ε Σ|x_i
          // y_i| (five additions and the products' rounding, to first order), so the two differ
          // by at most 12 ε Σ|x_i y_i|.
          const double scale = x.segment(a, width).cwiseAbs().dot(y.segment(b, width).cwiseAbs());
          CHECK(std::abs(ours - eigen) <= 12.0 * std::numeric_limits<double>::epsilon() * scale);
        }
      }
    }
  }
  CHECK(differing == 0);
  // long double takes Eigen's dot whatever the width.
  const Eigen::Matrix<long double, 6, 1> u = x.head<6>().cast<long double>();
  const Eigen::Matrix<long double, 6, 1> v = y.segment<6>(9).cast<long double>();
  const Eigen::Matrix<long double, Eigen::Dynamic, 1> ud = u, vd = v;
  CHECK(block_dot<long double>(u.data(), v.data(), 6) == ud.dot(vd));
}

}  // namespace
}  // namespace flexref::core
