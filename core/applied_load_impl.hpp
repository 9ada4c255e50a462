#pragma once
/// \file applied_load_impl.hpp
/// The definitions of applied_load.hpp's class templates, included where they are instantiated:
/// applied_load.cpp (double) and precision/element_conversion.cpp (long double, float128).
#include <cstddef>
#include <sstream>
#include <string>
#include <utility>

#include "core/applied_load.hpp"
#include "core/element_text.hpp"

namespace flexref::core {

template <typename S>
AppliedForceTpl<S>::AppliedForceTpl(int body, const Vector3& value, LoadFrame frame,
                                    const Vector3& p_BoP_B, TimeProfile profile,
                                    NodeAttachmentTpl<S> node)
    : body_(body),
      value_(value),
      frame_(frame),
      p_BoP_B_(p_BoP_B),
      profile_(profile),
      node_(std::move(node)) {}

template <typename S>
template <typename U>
AppliedForceTpl<S>::AppliedForceTpl(const AppliedForceTpl<U>& other)
    : body_(other.body_),
      value_(other.value_.template cast<S>()),
      frame_(other.frame_),
      p_BoP_B_(other.p_BoP_B_.template cast<S>()),
      profile_(other.profile_),
      node_(other.node_) {}

template <typename S>
typename AppliedForceTpl<S>::Vector3 AppliedForceTpl<S>::force_W(const Context& context,
                                                                 const Kinematics& body) const {
  const S scale = profile_.value_in(context.t, context.t_segment);
  return frame_ == LoadFrame::kWorld ? Vector3(scale * value_)
                                     : Vector3(body.R_WB * (scale * value_));
}

template <typename S>
void AppliedForceTpl<S>::add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                                      std::span<WrenchTpl<S>> wrenches) const {
  const auto i = static_cast<std::size_t>(body_);
  const Kinematics& body = bodies[i];
  const Vector3 f_W = force_W(context, body);
  if (!node_.deforms()) {
    wrenches[i].add_force_at(f_W, body.p_BrP_W(p_BoP_B_));
    return;
  }
  add_attached_force<S>(body, node_, f_W, attached_position_W<S>(body, p_BoP_B_, node_),
                        wrenches[i]);
}

template <typename S>
S AppliedForceTpl<S>::applied_power(const Context& context,
                                    std::span<const Kinematics> bodies) const {
  const Kinematics& body = bodies[static_cast<std::size_t>(body_)];
  const Vector3 p_WP = attached_position_W<S>(body, p_BoP_B_, node_);
  return force_W(context, body).dot(attached_velocity_W<S>(body, p_WP, node_));
}

template <typename S>
void AppliedForceTpl<S>::append_discontinuities(std::vector<double>& times) const {
  profile_.append_discontinuities(times);
}

template <typename S>
std::string AppliedForceTpl<S>::describe() const {
  return describe_with_names(std::span<const Body>{});
}

template <typename S>
std::string AppliedForceTpl<S>::describe_with_names(std::span<const Body> bodies) const {
  return "force " + vector_text(value_) + " N (" +
         (frame_ == LoadFrame::kWorld ? "world" : "body") + " frame) on " +
         body_text(body_, bodies) + " at " +
         (node_.deforms() ? node_text(body_, node_.node, bodies) + ", undeformed at point "
                          : std::string("point ")) +
         vector_text(p_BoP_B_) + ", " + profile_text(profile_);
}

template <typename S>
AppliedTorqueTpl<S>::AppliedTorqueTpl(int body, const Vector3& value, LoadFrame frame,
                                      TimeProfile profile)
    : body_(body), value_(value), frame_(frame), profile_(profile) {}

template <typename S>
template <typename U>
AppliedTorqueTpl<S>::AppliedTorqueTpl(const AppliedTorqueTpl<U>& other)
    : body_(other.body_),
      value_(other.value_.template cast<S>()),
      frame_(other.frame_),
      profile_(other.profile_) {}

template <typename S>
void AppliedTorqueTpl<S>::add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                                       std::span<WrenchTpl<S>> wrenches) const {
  const auto i = static_cast<std::size_t>(body_);
  const S scale = profile_.value_in(context.t, context.t_segment);
  if (frame_ == LoadFrame::kWorld) {
    wrenches[i].tau_Br_W += scale * value_;
  } else {
    wrenches[i].tau_Br_W += bodies[i].R_WB * (scale * value_);
  }
}

template <typename S>
S AppliedTorqueTpl<S>::applied_power(const Context& context,
                                     std::span<const Kinematics> bodies) const {
  const Kinematics& body = bodies[static_cast<std::size_t>(body_)];
  const S scale = profile_.value_in(context.t, context.t_segment);
  const Vector3 tau_W =
      frame_ == LoadFrame::kWorld ? Vector3(scale * value_) : Vector3(body.R_WB * (scale * value_));
  // Γ · ω, ω = A ω̄ in the world.
  return tau_W.dot(body.R_WB * body.state->w_WB_B);
}

template <typename S>
void AppliedTorqueTpl<S>::append_discontinuities(std::vector<double>& times) const {
  profile_.append_discontinuities(times);
}

template <typename S>
std::string AppliedTorqueTpl<S>::describe() const {
  return describe_with_names(std::span<const Body>{});
}

template <typename S>
std::string AppliedTorqueTpl<S>::describe_with_names(std::span<const Body> bodies) const {
  return "torque " + vector_text(value_) + " N·m (" +
         (frame_ == LoadFrame::kWorld ? "world" : "body") + " frame) on " +
         body_text(body_, bodies) + ", " + profile_text(profile_);
}

}  // namespace flexref::core
