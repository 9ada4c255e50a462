#include "core/applied_load.hpp"

#include <cstddef>
#include <sstream>
#include <string>
#include <utility>

namespace flexref::core {
namespace {

std::string profile_text(const TimeProfile& p) {
  std::ostringstream out;
  switch (p.shape()) {
    case TimeProfile::Shape::kConstant:
      return "constant";
    case TimeProfile::Shape::kSin2Pulse:
      out << "sin2 pulse on [" << p.start() << ", " << p.start() + p.duration() << ")";
      return out.str();
    case TimeProfile::Shape::kRectangularPulse:
      out << "rectangular pulse on [" << p.start() << ", " << p.start() + p.duration() << ")";
      return out.str();
    case TimeProfile::Shape::kHarmonic:
      out << "harmonic sin(2 pi " << p.frequency() << " Hz t + " << p.phase() << ")";
      return out.str();
  }
  return {};
}

std::string vector_text(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return out.str();
}

}  // namespace

AppliedForce::AppliedForce(int body, const Eigen::Vector3d& value, LoadFrame frame,
                           const Eigen::Vector3d& p_BoP_B, TimeProfile profile, NodeAttachment node)
    : body_(body),
      value_(value),
      frame_(frame),
      p_BoP_B_(p_BoP_B),
      profile_(profile),
      node_(std::move(node)) {}

Eigen::Vector3d AppliedForce::force_W(const LoadContext& context,
                                      const BodyKinematics& body) const {
  const double scale = profile_.value(context.t, context.t_segment);
  return frame_ == LoadFrame::kWorld ? Eigen::Vector3d(scale * value_)
                                     : Eigen::Vector3d(body.R_WB * (scale * value_));
}

void AppliedForce::add_wrenches(const LoadContext& context, std::span<const BodyKinematics> bodies,
                                std::span<Wrench> wrenches) const {
  const auto i = static_cast<std::size_t>(body_);
  const BodyKinematics& body = bodies[i];
  const Eigen::Vector3d f_W = force_W(context, body);
  if (!node_.deforms()) {
    wrenches[i].add_force_at(f_W, body.p_BrP_W(p_BoP_B_));
    return;
  }
  add_attached_force(body, node_, f_W, attached_position_W(body, p_BoP_B_, node_), wrenches[i]);
}

double AppliedForce::applied_power(const LoadContext& context,
                                   std::span<const BodyKinematics> bodies) const {
  const BodyKinematics& body = bodies[static_cast<std::size_t>(body_)];
  const Eigen::Vector3d p_WP = attached_position_W(body, p_BoP_B_, node_);
  return force_W(context, body).dot(attached_velocity_W(body, p_WP, node_));
}

void AppliedForce::append_discontinuities(std::vector<double>& times) const {
  profile_.append_discontinuities(times);
}

std::string AppliedForce::describe() const {
  return "force " + vector_text(value_) + " N (" +
         (frame_ == LoadFrame::kWorld ? "world" : "body") + " frame) at body point " +
         vector_text(p_BoP_B_) +
         (node_.deforms() ? " (node " + std::to_string(node_.node) + ")" : "") + ", " +
         profile_text(profile_);
}

AppliedTorque::AppliedTorque(int body, const Eigen::Vector3d& value, LoadFrame frame,
                             TimeProfile profile)
    : body_(body), value_(value), frame_(frame), profile_(profile) {}

void AppliedTorque::add_wrenches(const LoadContext& context, std::span<const BodyKinematics> bodies,
                                 std::span<Wrench> wrenches) const {
  const auto i = static_cast<std::size_t>(body_);
  const double scale = profile_.value(context.t, context.t_segment);
  if (frame_ == LoadFrame::kWorld) {
    wrenches[i].tau_Br_W += scale * value_;
  } else {
    wrenches[i].tau_Br_W += bodies[i].R_WB * (scale * value_);
  }
}

void AppliedTorque::append_discontinuities(std::vector<double>& times) const {
  profile_.append_discontinuities(times);
}

std::string AppliedTorque::describe() const {
  return "torque " + vector_text(value_) + " N·m (" +
         (frame_ == LoadFrame::kWorld ? "world" : "body") + " frame), " + profile_text(profile_);
}

}  // namespace flexref::core
