#pragma once
/// \file bushing_tpl.hpp
/// The bushing equations of contact/bushing.hpp written once for any scalar type S: the element
/// BushingTpl<S, kRevolute> (spherical and revolute) calls them in every precision (double,
/// long double, float128; docs/precision.md). The stiffness and damping stay the scene's doubles.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "contact/bushing.hpp"

namespace flexref::contact::bushing {

template <typename S>
using Vector3 = Eigen::Matrix<S, 3, 1>;

/// The pose and velocity of one end, world frame; the ground is at rest with R = I.
template <typename S>
struct EndMotion {
  bool ground = true;
  Vector3<S> p_WP = Vector3<S>::Zero();   ///< attachment point
  Vector3<S> p_WBr = Vector3<S>::Zero();  ///< reference point Br
  Vector3<S> v_WBr = Vector3<S>::Zero();
  Vector3<S> w_WB_W = Vector3<S>::Zero();
  Vector3<S> axis_W = Vector3<S>::UnitZ();
  /// Velocity of the body's material point now at p_WM: v_Br + ω × (p_WM − p_WBr).
  Vector3<S> v_WM(const Vector3<S>& p_WM) const { return v_WBr + w_WB_W.cross(p_WM - p_WBr); }
};

/// The spherical part: d = p_WQ − p_WP, midpoint M, u = v_B(M) − v_A(M).
template <typename S>
struct Separation {
  Vector3<S> d_W;
  Vector3<S> p_WM;
  Vector3<S> u_W;
};

template <typename S>
Separation<S> separation(const EndMotion<S>& a, const EndMotion<S>& b) {
  Separation<S> s;
  s.d_W = b.p_WP - a.p_WP;
  s.p_WM = a.p_WP + S(0.5) * s.d_W;
  s.u_W = b.v_WM(s.p_WM) - a.v_WM(s.p_WM);
  return s;
}

/// f = k d + c u, on A at M (−f on B at M).
template <typename S>
Vector3<S> spherical_force(const Separation<S>& s, const BushingParameters& p) {
  return S(p.stiffness) * s.d_W + S(p.damping) * s.u_W;
}

/// P ω_rel with P = I − ½(a_A a_Aᵀ + a_B a_Bᵀ), without forming P.
template <typename S>
Vector3<S> perpendicular_part(const EndMotion<S>& a, const EndMotion<S>& b, const Vector3<S>& w_W) {
  return w_W - S(0.5) * (a.axis_W * a.axis_W.dot(w_W) + b.axis_W * b.axis_W.dot(w_W));
}

/// τ_A = k_θ a_A × a_B + c_θ P (ω_B − ω_A) (τ_B = −τ_A).
template <typename S>
Vector3<S> revolute_torque(const EndMotion<S>& a, const EndMotion<S>& b,
                           const BushingParameters& p) {
  return S(p.angular_stiffness) * a.axis_W.cross(b.axis_W) +
         S(p.angular_damping) * perpendicular_part(a, b, Vector3<S>(b.w_WB_W - a.w_WB_W));
}

/// ½k|d|² (+ k_θ(1 − a_Aᵀa_B) = ½k_θ|a_A − a_B|² for unit axes, without cancellation).
template <typename S>
S potential(const EndMotion<S>& a, const EndMotion<S>& b, const BushingParameters& p,
            bool revolute) {
  S v = S(0.5) * S(p.stiffness) * (b.p_WP - a.p_WP).squaredNorm();
  if (revolute) v += S(0.5) * S(p.angular_stiffness) * (a.axis_W - b.axis_W).squaredNorm();
  return v;
}

/// c|u|² (+ c_θ ω_relᵀ P ω_rel): the power the dampers take, ≥ 0.
template <typename S>
S dissipated_power(const EndMotion<S>& a, const EndMotion<S>& b, const BushingParameters& p,
                   bool revolute) {
  if (!revolute) {
    if (p.damping == 0.0) return S(0);
    return S(p.damping) * separation(a, b).u_W.squaredNorm();
  }
  const Separation<S> s = separation(a, b);
  const Vector3<S> w_rel_W = b.w_WB_W - a.w_WB_W;
  return S(p.damping) * s.u_W.squaredNorm() +
         S(p.angular_damping) * w_rel_W.dot(perpendicular_part(a, b, w_rel_W));
}

}  // namespace flexref::contact::bushing
