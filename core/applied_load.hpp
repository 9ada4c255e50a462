#pragma once
/// \file applied_load.hpp
/// Prescribed loads: a force at a body point or a pure torque, given in the world or the
/// body frame, scaled by a time profile. Non-conservative: no potential energy. Generic in the
/// scalar type S (core/force_element.hpp); the definitions are applied_load_impl.hpp's.
#include <limits>
#include <string>
#include <vector>

#include "core/force_element.hpp"
#include "core/node_attachment.hpp"
#include "core/time_profile.hpp"

namespace flexref::core {

enum class LoadFrame { kWorld, kBody };

/// f(t) = profile(t) · value, applied at the body point p_BoP_B — at a node of a flexible body
/// when `node` deforms (core/node_attachment.hpp: the deformed point, Φ_kᵀ Aᵀ f in the modal
/// rows). Its work is tracked (applied_work, docs/output.md).
template <typename S>
class AppliedForceTpl final : public ForceElementTpl<S> {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using typename ForceElementTpl<S>::Context;
  using typename ForceElementTpl<S>::Kinematics;

  AppliedForceTpl(int body, const Vector3& value, LoadFrame frame, const Vector3& p_BoP_B,
                  TimeProfile profile, NodeAttachmentTpl<S> node = {});
  /// The same load in another scalar type.
  template <typename U>
  explicit AppliedForceTpl(const AppliedForceTpl<U>& other);

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<WrenchTpl<S>> wrenches) const override;
  /// A prescribed force does work whatever its profile (constant, pulse, harmonic): tracked as
  /// W_a wherever the model tracks work (Model::tracks_applied_work).
  bool tracks_applied_work() const override { return true; }
  /// f · v_P, v_P the velocity of the (deformed) point.
  S applied_power(const Context& context, std::span<const Kinematics> bodies) const override;
  /// Its work is in the balance throughout (a model that does not track work uses loads_end).
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  double loads_end() const override { return profile_.end(); }
  void append_discontinuities(std::vector<double>& times) const override;
  std::string describe() const override;
  std::string describe_with_names(std::span<const Body> bodies) const override;
  int max_body_index() const override { return body_; }
  std::vector<int> coupled_bodies() const override { return {body_}; }

 private:
  template <typename>
  friend class AppliedForceTpl;

  int body_;
  Vector3 value_;
  LoadFrame frame_;
  Vector3 p_BoP_B_;
  TimeProfile profile_;
  NodeAttachmentTpl<S> node_;

  Vector3 force_W(const Context& context, const Kinematics& body) const;
};

/// Γ(t) = profile(t) · value, a pure torque (couple).
template <typename S>
class AppliedTorqueTpl final : public ForceElementTpl<S> {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using typename ForceElementTpl<S>::Context;
  using typename ForceElementTpl<S>::Kinematics;

  AppliedTorqueTpl(int body, const Vector3& value, LoadFrame frame, TimeProfile profile);
  /// The same load in another scalar type.
  template <typename U>
  explicit AppliedTorqueTpl(const AppliedTorqueTpl<U>& other);

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<WrenchTpl<S>> wrenches) const override;
  /// A torque's work is never tracked: in the balance only once its profile has ended.
  /// Tracked like a force's (W_a): Γ · ω.
  bool tracks_applied_work() const override { return true; }
  S applied_power(const Context& context, std::span<const Kinematics> bodies) const override;
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  double loads_end() const override { return profile_.end(); }
  void append_discontinuities(std::vector<double>& times) const override;
  std::string describe() const override;
  std::string describe_with_names(std::span<const Body> bodies) const override;
  int max_body_index() const override { return body_; }
  std::vector<int> coupled_bodies() const override { return {body_}; }

 private:
  template <typename>
  friend class AppliedTorqueTpl;

  int body_;
  Vector3 value_;
  LoadFrame frame_;
  TimeProfile profile_;
};

using AppliedForce = AppliedForceTpl<double>;
using AppliedTorque = AppliedTorqueTpl<double>;
extern template class AppliedForceTpl<double>;
extern template class AppliedTorqueTpl<double>;

}  // namespace flexref::core
