#pragma once
/// \file gap_support_tpl.hpp
/// The gap support's geometry (docs/contact.md, "Gap support"; gap_support.hpp; its load is
/// penalty_load_tpl.hpp's) written once, generic in the scalar type S: GapSupportTpl<S> calls
/// it in every precision (double for core::Model, long double and float128 for the extended/quad
/// references). The parameters are the scene's doubles, exact in S.
///   circular  d = (I − a aᵀ)(p_WN − p_WS),  g = c − |d|,  n = −d/|d|
///   planar    s = m·(p_WN − p_WS),          g = c − |s|,  n = −sign(s) m
/// and, while g < 0, the load of penalty_load_tpl.hpp at the node (v_rel = v_N, its velocity).
#include <Eigen/Core>
#include <cmath>

namespace flexref::contact {

/// The support's data in S (GapSupportGeometry's, unit axis and normal as it normalized them).
template <typename S>
struct GapGeometryTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  bool circular = true;
  Vector3 p_WS = Vector3::Zero();
  Vector3 a_W = Vector3::UnitX();
  Vector3 m_W = Vector3::UnitZ();
  S clearance = S(0);
};

/// Gap and normal at the (deformed) point p_WN.
template <typename S>
struct GapPointTpl {
  S gap = S(0);
  Eigen::Matrix<S, 3, 1> n_W = Eigen::Matrix<S, 3, 1>::UnitZ();  ///< on the body, toward the axis
};

template <typename S>
GapPointTpl<S> gap_point_tpl(const GapGeometryTpl<S>& geometry,
                             const Eigen::Matrix<S, 3, 1>& p_WN) {
  using std::abs;
  using std::sqrt;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  GapPointTpl<S> c;
  const Vector3 r = p_WN - geometry.p_WS;
  if (geometry.circular) {
    const Vector3 d = r - geometry.a_W.dot(r) * geometry.a_W;  // (I − a aᵀ) r
    const S distance = sqrt(d.squaredNorm());
    c.gap = geometry.clearance - distance;
    // On the axis there is no direction, and no force (g = c > 0).
    c.n_W = distance > S(0) ? Vector3(-d / distance) : geometry.m_W;
  } else {
    const S s = geometry.m_W.dot(r);
    c.gap = geometry.clearance - abs(s);
    c.n_W = s >= S(0) ? Vector3(-geometry.m_W) : geometry.m_W;
  }
  return c;
}

}  // namespace flexref::contact
