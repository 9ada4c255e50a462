#pragma once
/// \file gravity.hpp
/// Uniform gravity g_W on every body: f = m g at the centre of mass (docs/design/model.md:
/// Qe_R += m g, Qe_θ += s̃ Aᵀ g), potential V = −Σ m g·p_WBcm; on a flexible body the loads on
/// its invariants (add_gravity_loads_tpl). Generic in the scalar type S (core/force_element.hpp);
/// the definitions are gravity_impl.hpp's.
#include <limits>
#include <string>
#include <vector>

#include "core/force_element.hpp"

namespace flexref::core {

template <typename S>
class UniformGravityTpl final : public ForceElementTpl<S> {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using typename ForceElementTpl<S>::Context;
  using typename ForceElementTpl<S>::Kinematics;

  struct BodyMass {
    int body = 0;
    S mass = S(0);
    Vector3 p_BoBcm_B = Vector3::Zero();
  };

  UniformGravityTpl(const Vector3& g_W, std::vector<BodyMass> bodies);
  /// The same field in another scalar type.
  template <typename U>
  explicit UniformGravityTpl(const UniformGravityTpl<U>& other);

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<WrenchTpl<S>> wrenches) const override;
  S potential_energy(const Context& context, std::span<const Kinematics> bodies) const override;
  /// Conservative: its work is its potential energy.
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  std::string describe() const override;
  int max_body_index() const override;
  /// None: each body's weight depends on that body alone.
  std::vector<int> coupled_bodies() const override { return {}; }
  const Vector3& g_W() const { return g_W_; }

 private:
  template <typename>
  friend class UniformGravityTpl;

  Vector3 g_W_;
  std::vector<BodyMass> bodies_;
};

using UniformGravity = UniformGravityTpl<double>;
extern template class UniformGravityTpl<double>;

}  // namespace flexref::core
