#pragma once
/// \file block_dot_tpl.hpp
/// The dot product of two body blocks of the joints' sparse matrices (J, Y = M⁻¹ J_aᵀ, the
/// accepted rows: core/constraint_jacobian_tpl.hpp), the inner operation of the Schur
/// complement's entries, the rows' products and the orientation test (docs/decisions.md,
/// "Constrained systems at scale"). A rigid body's block is 6 wide; Eigen's dot of a
/// run-time-sized block spends more on its set-up (size, alignment, packet loop) than on those
/// six products, so the 6-wide double block is written out. Its order of summation is that of
/// Eigen's run-time-sized dot on x86-64's SSE2 packets of two doubles — even and odd
/// coefficients summed apart, then added — so that the results are unchanged bit for bit
/// (tests/core/block_dot_test.cpp checks it against Eigen's); other widths and scalar types
/// take Eigen's dot itself.
#include <Eigen/Core>
#include <type_traits>

namespace flexref::core {

/// Eigen's dot of x[0 .. width) and y[0 .. width) (block_dot's general case, apart so that
/// block_dot stays small enough to be inlined).
template <typename S>
S dynamic_block_dot(const S* x, const S* y, int width) {
  using Map = Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, 1>>;
  return Map(x, width).dot(Map(y, width));
}

/// x[0 .. width) · y[0 .. width).
template <typename S>
inline S block_dot(const S* x, const S* y, int width) {
  if constexpr (std::is_same_v<S, double>) {
    if (width == 6) {
      const double even = (x[0] * y[0] + x[2] * y[2]) + x[4] * y[4];
      const double odd = (x[1] * y[1] + x[3] * y[3]) + x[5] * y[5];
      return even + odd;
    }
  }
  return dynamic_block_dot<S>(x, y, width);
}

}  // namespace flexref::core
