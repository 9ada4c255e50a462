#pragma once
/// \file unit_vector_tpl.hpp
/// A direction the double model stores as a unit vector (a plane normal, a support axis, a
/// prescribed rotation axis: normalized in double, |n| = 1 only to ~1e-16) as a unit vector of
/// the precision S. In double it is the stored vector, bit for bit. In a longer precision it is
/// normalized again in S: otherwise n·n − 1 ~ 1e-16 would show in S's solution, e.g. the slip
/// v − (n·v) n would keep a part along n, friction would do work there that its dissipation
/// −F_t·v_t does not count, and the energy balance of a quad solution would close only to
/// ~1e-16 relative (docs/precision.md). The two models differ by that rounding of the data, far
/// below the double solution's own error.
#include <Eigen/Core>
#include <cmath>
#include <type_traits>

namespace flexref::core {

template <typename S>
Eigen::Matrix<S, 3, 1> unit_vector_as(const Eigen::Vector3d& n) {
  if constexpr (std::is_same_v<S, double>) {
    return n;
  } else {
    using std::sqrt;
    const Eigen::Matrix<S, 3, 1> v = n.cast<S>();
    const S norm = sqrt(v.squaredNorm());
    // A zero vector (a circular gap support's unused plane normal, say) stays zero, not NaN.
    return norm > S(0) ? Eigen::Matrix<S, 3, 1>(v / norm) : v;
  }
}

}  // namespace flexref::core
