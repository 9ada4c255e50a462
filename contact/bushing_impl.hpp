#pragma once
/// \file bushing_impl.hpp
/// The definitions of bushing.hpp's class templates, included where they are instantiated:
/// bushing.cpp (double) and precision/element_conversion.cpp (long double, float128).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "contact/bushing.hpp"
#include "contact/bushing_tpl.hpp"
#include "core/element_text.hpp"
#include "core/unit_vector_tpl.hpp"

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
          core::unit_vector_in<S>(end.axis.template cast<double>())};
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
std::string BushingTpl<S, kRevolute>::describe() const {
  std::ostringstream out;
  out << (kRevolute ? "revolute" : "spherical") << " bushing: "
      << detail::bushing_ends_text(detail::end_in_double(a_), detail::end_in_double(b_));
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
