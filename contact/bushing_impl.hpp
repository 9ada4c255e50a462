#pragma once
/// \file bushing_impl.hpp
/// The definitions of bushing.hpp's class templates, included where they are instantiated:
/// bushing.cpp (double) and precision/element_conversion.cpp (long double, float128).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "contact/bushing.hpp"
#include "core/element_text.hpp"
#include "core/unit_vector_tpl.hpp"

namespace flexref::contact::bushing {

// The bushing equations, written once for any scalar type S; the stiffness and damping stay the
// scene's doubles.

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

namespace flexref::contact {
namespace detail {

template <typename S>
BushingEnd end_in_double(const BushingEndTpl<S>& end) {
  return {end.body, end.point.template cast<double>(), end.axis.template cast<double>()};
}

/// An end in S from one in U: the point exact, the axis a unit vector of S
/// (core/unit_vector_tpl.hpp).
template <typename S, typename U>
BushingEndTpl<S> end_in(const BushingEndTpl<U>& end) {
  return {end.body, end.point.template cast<S>(),
          core::unit_vector_as<S>(end.axis.template cast<double>())};
}

/// The pose and velocity of an end: a body's hub point p_WBr + A (P − Bo − p_BoBr), its Br, v_Br,
/// ω = A ω̄ and axis A ā; the ground's as given.
template <typename S>
bushing::EndMotion<S> end_motion(const BushingEndTpl<S>& end,
                                 std::span<const core::BodyKinematicsTpl<S>> bodies) {
  bushing::EndMotion<S> m;
  if (end.body == kGround) {
    m.p_WP = end.point;
    m.axis_W = end.axis;
    return m;
  }
  const core::BodyKinematicsTpl<S>& k = bodies[static_cast<std::size_t>(end.body)];
  m.ground = false;
  m.p_WP = k.p_WP(end.point);
  m.p_WBr = k.state->p_WBr;
  m.v_WBr = k.state->v_WBr;
  m.w_WB_W = k.R_WB * k.state->w_WB_B;
  m.axis_W = k.R_WB * end.axis;
  return m;
}

/// f = k d + c u on A at M, −f on B at M.
template <typename S>
void add_spherical(const BushingEndTpl<S>& a_end, const BushingEndTpl<S>& b_end,
                   const bushing::EndMotion<S>& a, const bushing::EndMotion<S>& b,
                   const BushingParameters& p, std::span<core::WrenchTpl<S>> wrenches) {
  const bushing::Separation<S> s = bushing::separation(a, b);
  const Eigen::Matrix<S, 3, 1> f_W = bushing::spherical_force(s, p);
  wrenches[static_cast<std::size_t>(a_end.body)].add_force_at(f_W, s.p_WM - a.p_WBr);
  if (!b.ground) {
    wrenches[static_cast<std::size_t>(b_end.body)].add_force_at(-f_W, s.p_WM - b.p_WBr);
  }
}

}  // namespace detail

template <typename S, bool kRevolute>
BushingTpl<S, kRevolute>::BushingTpl(const BushingEndTpl<S>& a, const BushingEndTpl<S>& b,
                                     const BushingParameters& parameters)
    : a_(a), b_(b), parameters_(parameters) {
  detail::validate_bushing(detail::end_in_double(a_), detail::end_in_double(b_), parameters_,
                           kRevolute);
  if constexpr (kRevolute) {
    a_.axis.normalize();
    b_.axis.normalize();
  } else {
    parameters_.angular_stiffness = 0.0;
    parameters_.angular_damping = 0.0;
  }
}

template <typename S, bool kRevolute>
template <typename U>
BushingTpl<S, kRevolute>::BushingTpl(const BushingTpl<U, kRevolute>& other)
    : a_(detail::end_in<S>(other.a_)),
      b_(detail::end_in<S>(other.b_)),
      parameters_(other.parameters_) {}

template <typename S, bool kRevolute>
void BushingTpl<S, kRevolute>::add_wrenches(const Context& context,
                                            std::span<const Kinematics> bodies,
                                            std::span<core::WrenchTpl<S>> wrenches) const {
  add_wrenches_and_rates(context, bodies, wrenches, nullptr, {}, {}, {});
}

template <typename S, bool kRevolute>
void BushingTpl<S, kRevolute>::add_wrenches_and_rates(const Context& /*context*/,
                                                      std::span<const Kinematics> bodies,
                                                      std::span<core::WrenchTpl<S>> wrenches,
                                                      S* dissipated,
                                                      std::span<core::WearSampleTpl<S>> /*wear*/,
                                                      std::span<S> /*gaps*/,
                                                      std::span<S> /*clamps*/) const {
  const bushing::EndMotion<S> a = detail::end_motion(a_, bodies);
  const bushing::EndMotion<S> b = detail::end_motion(b_, bodies);
  detail::add_spherical<S>(a_, b_, a, b, parameters_, wrenches);
  if (dissipated != nullptr) {
    *dissipated += bushing::dissipated_power(a, b, parameters_, kRevolute);
  }
  if constexpr (kRevolute) {
    using std::sqrt;
    // τ_A = k_θ a_A × a_B + c_θ P (ω_B − ω_A), τ_B = −τ_A.
    const Eigen::Matrix<S, 3, 1> tau_W = bushing::revolute_torque(a, b, parameters_);
    const S tau_norm = sqrt(tau_W.squaredNorm());
    wrenches[static_cast<std::size_t>(a_.body)].tau_Br_W += tau_W;
    wrenches[static_cast<std::size_t>(a_.body)].torque_magnitude += tau_norm;
    if (!b.ground) {
      wrenches[static_cast<std::size_t>(b_.body)].tau_Br_W -= tau_W;
      wrenches[static_cast<std::size_t>(b_.body)].torque_magnitude += tau_norm;
    }
  }
}

template <typename S, bool kRevolute>
S BushingTpl<S, kRevolute>::potential_energy(const Context& /*context*/,
                                             std::span<const Kinematics> bodies) const {
  return bushing::potential(detail::end_motion(a_, bodies), detail::end_motion(b_, bodies),
                            parameters_, kRevolute);
}

template <typename S, bool kRevolute>
S BushingTpl<S, kRevolute>::dissipated_power(const Context& /*context*/,
                                             std::span<const Kinematics> bodies) const {
  return bushing::dissipated_power(detail::end_motion(a_, bodies), detail::end_motion(b_, bodies),
                                   parameters_, kRevolute);
}

template <typename S, bool kRevolute>
int BushingTpl<S, kRevolute>::max_body_index() const {
  return std::max(a_.body, b_.body);
}

template <typename S, bool kRevolute>
std::vector<int> BushingTpl<S, kRevolute>::coupled_bodies() const {
  if (b_.body == kGround) return {a_.body};
  return {a_.body, b_.body};
}

template <typename S, bool kRevolute>
std::string BushingTpl<S, kRevolute>::describe() const {
  return describe_with_names(std::span<const core::Body>{});
}

template <typename S, bool kRevolute>
std::string BushingTpl<S, kRevolute>::describe_with_names(
    std::span<const core::Body> bodies) const {
  std::ostringstream out;
  out << (kRevolute ? "revolute" : "spherical") << " bushing: "
      << detail::bushing_ends_text(detail::end_in_double(a_), detail::end_in_double(b_), bodies);
  if constexpr (kRevolute) {
    out << ", hinge axis " << core::vector_text(a_.axis)
        << (b_.body == kGround ? " / world " : " / ") << core::vector_text(b_.axis);
  }
  out << ", k = " << parameters_.stiffness << " N/m, c = " << parameters_.damping << " N·s/m";
  if constexpr (kRevolute) {
    out << ", k_theta = " << parameters_.angular_stiffness
        << " N·m/rad, c_theta = " << parameters_.angular_damping << " N·m·s/rad";
  }
  return out.str();
}

template <typename S, bool kRevolute>
void BushingTpl<S, kRevolute>::append_penalty_modes(std::span<const core::Body> bodies,
                                                    std::vector<core::PenaltyMode>& modes) const {
  detail::append_bushing_modes(bodies, detail::end_in_double(a_), detail::end_in_double(b_),
                               parameters_, kRevolute, modes);
}

}  // namespace flexref::contact
