#pragma once
/// \file contact_point_tpl.hpp
/// The geometry of a sphere–plane and a sphere–sphere pair (contact.hpp, docs/contact.md),
/// written once, generic in the scalar type S: ContactElementTpl<S> calls it in every precision
/// (double for core::Model, long double and float128 for the extended/quad references).
///   sphere–plane:  g = n·(p_WCb − p_WQ) − r_b,  P = C_b − r_b n  (n the plane's unit normal)
///   sphere–sphere: d = C_b − C_a,  g = |d| − r_a − r_b,  n = d/|d|,  P = C_a + (r_a + g/2) n
/// (coincident centres have no direction: n = e_z). n points from a (or the plane) to b.
#include <Eigen/Core>
#include <cmath>

namespace flexref::contact {

template <typename S>
struct ContactPointTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  S gap = S(0);                    ///< m
  Vector3 n_W = Vector3::UnitZ();  ///< unit normal, a → b
  Vector3 p_WP = Vector3::Zero();  ///< contact point, world
};

template <typename S>
ContactPointTpl<S> sphere_plane_point_tpl(const Eigen::Matrix<S, 3, 1>& p_WCb, const S& radius_b,
                                          const Eigen::Matrix<S, 3, 1>& p_WQ,
                                          const Eigen::Matrix<S, 3, 1>& n_W) {
  ContactPointTpl<S> c;
  c.n_W = n_W;
  c.gap = n_W.dot(p_WCb - p_WQ) - radius_b;
  c.p_WP = p_WCb - radius_b * n_W;
  return c;
}

template <typename S>
ContactPointTpl<S> sphere_sphere_point_tpl(const Eigen::Matrix<S, 3, 1>& p_WCa, const S& radius_a,
                                           const Eigen::Matrix<S, 3, 1>& p_WCb, const S& radius_b) {
  using std::sqrt;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  ContactPointTpl<S> c;
  const Vector3 d = p_WCb - p_WCa;
  const S distance = sqrt(d.squaredNorm());
  c.n_W = distance > S(0) ? Vector3(d / distance) : Vector3::UnitZ();
  c.gap = distance - radius_a - radius_b;
  c.p_WP = p_WCa + (radius_a + S(0.5) * c.gap) * c.n_W;
  return c;
}

}  // namespace flexref::contact
