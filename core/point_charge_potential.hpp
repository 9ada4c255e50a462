#pragma once
/// \file point_charge_potential.hpp
/// The soft Coulomb wall of the paper's Fig. 2: charges c_i at body points P_i, attracted to
/// a fixed point M and repelled by the wall z = 0 (docs/design/scenes.md, `coulomb_wall`):
///   V = Σ_i c_i ( −α/|r_i − M| + β/z_i ),
///   f_i = −∇V = −c_i α (r_i − M)/|r_i − M|³ + c_i β/z_i² e_z.
/// Conservative: the energy output includes V. Generic in the scalar type S
/// (core/force_element.hpp); the definitions are point_charge_potential_impl.hpp's.
#include <limits>
#include <string>
#include <vector>

#include "core/force_element.hpp"

namespace flexref::core {

template <typename S>
class PointChargePotentialTpl final : public ForceElementTpl<S> {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using typename ForceElementTpl<S>::Context;
  using typename ForceElementTpl<S>::Kinematics;

  struct Charge {
    int body = 0;
    Vector3 p_BoP_B = Vector3::Zero();
    S weight = S(1);  ///< c_i
  };

  PointChargePotentialTpl(S alpha, S beta, const Vector3& p_WM, std::vector<Charge> charges);
  /// The same potential in another scalar type.
  template <typename U>
  explicit PointChargePotentialTpl(const PointChargePotentialTpl<U>& other);

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<WrenchTpl<S>> wrenches) const override;
  S potential_energy(const Context& context, std::span<const Kinematics> bodies) const override;
  /// Conservative: its work is its potential energy.
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  std::string describe() const override;
  int max_body_index() const override;
  /// None: each charge's load depends on its own body's pose alone (the attractor is fixed).
  std::vector<int> coupled_bodies() const override { return {}; }

  /// Force on a unit-weight charge at r (world); exposed for derivative tests.
  Vector3 unit_force_W(const Vector3& p_WP) const;
  /// Potential of a unit-weight charge at r.
  S unit_potential(const Vector3& p_WP) const;
  const std::vector<Charge>& charges() const { return charges_; }

 private:
  template <typename>
  friend class PointChargePotentialTpl;

  S alpha_;
  S beta_;
  Vector3 p_WM_;
  std::vector<Charge> charges_;

  /// The unit charge's force and potential at r, both from one evaluation.
  void unit_field(const Vector3& p_WP, Vector3& f_W, S& potential) const;
};

using PointChargePotential = PointChargePotentialTpl<double>;
extern template class PointChargePotentialTpl<double>;

}  // namespace flexref::core
