#pragma once
/// \file applied_load.hpp
/// Prescribed loads: a force at a body point or a pure torque, given in the world or the
/// body frame, scaled by a time profile. Non-conservative: no potential energy.
#include "core/force_element.hpp"
#include "core/node_attachment.hpp"
#include "core/time_profile.hpp"

namespace flexref::core {

enum class LoadFrame { kWorld, kBody };

/// f(t) = profile(t) · value, applied at the body point p_BoP_B — at a node of a flexible body
/// when `node` deforms (core/node_attachment.hpp: the deformed point, Φ_kᵀ Aᵀ f in the modal
/// rows). A harmonic force's work is tracked (applied_work, docs/output.md).
class AppliedForce final : public ForceElement {
 public:
  AppliedForce(int body, const Eigen::Vector3d& value, LoadFrame frame,
               const Eigen::Vector3d& p_BoP_B, TimeProfile profile, NodeAttachment node = {});
  void add_wrenches(const LoadContext& context, std::span<const BodyKinematics> bodies,
                    std::span<Wrench> wrenches) const override;
  bool tracks_applied_work() const override {
    return profile_.shape() == TimeProfile::Shape::kHarmonic;
  }
  /// f · v_P, v_P the velocity of the (deformed) point.
  double applied_power(const LoadContext& context,
                       std::span<const BodyKinematics> bodies) const override;
  void append_discontinuities(std::vector<double>& times) const override;
  std::string describe() const override;
  int max_body_index() const override { return body_; }

 private:
  int body_;
  Eigen::Vector3d value_;
  LoadFrame frame_;
  Eigen::Vector3d p_BoP_B_;
  TimeProfile profile_;
  NodeAttachment node_;

  Eigen::Vector3d force_W(const LoadContext& context, const BodyKinematics& body) const;
};

/// Γ(t) = profile(t) · value, a pure torque (couple).
class AppliedTorque final : public ForceElement {
 public:
  AppliedTorque(int body, const Eigen::Vector3d& value, LoadFrame frame, TimeProfile profile);
  void add_wrenches(const LoadContext& context, std::span<const BodyKinematics> bodies,
                    std::span<Wrench> wrenches) const override;
  void append_discontinuities(std::vector<double>& times) const override;
  std::string describe() const override;
  int max_body_index() const override { return body_; }

 private:
  int body_;
  Eigen::Vector3d value_;
  LoadFrame frame_;
  TimeProfile profile_;
};

}  // namespace flexref::core
