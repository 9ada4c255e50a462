#pragma once
/// \file point_charge_potential.hpp
/// The soft Coulomb wall of the paper's Fig. 2: charges c_i at body points P_i, attracted to
/// a fixed point M and repelled by the wall z = 0 (docs/design/scenes.md, `coulomb_wall`):
///   V = Σ_i c_i ( −α/|r_i − M| + β/z_i ),
///   f_i = −∇V = −c_i α (r_i − M)/|r_i − M|³ + c_i β/z_i² e_z.
/// Conservative: the energy output includes V.
#include <cmath>
#include <vector>

#include "core/force_element.hpp"

namespace flexref::core {

class PointChargePotential final : public ForceElement {
 public:
  struct Charge {
    int body = 0;
    Eigen::Vector3d p_BoP_B = Eigen::Vector3d::Zero();
    double weight = 1.0;  ///< c_i
  };

  PointChargePotential(double alpha, double beta, const Eigen::Vector3d& p_WM,
                       std::vector<Charge> charges);
  void add_wrenches(const LoadContext& context, std::span<const BodyKinematics> bodies,
                    std::span<Wrench> wrenches) const override;
  double potential_energy(const LoadContext& context,
                          std::span<const BodyKinematics> bodies) const override;
  std::string describe() const override;
  int max_body_index() const override;

  /// Force on a unit-weight charge at r (world); exposed for derivative tests.
  Eigen::Vector3d unit_force_W(const Eigen::Vector3d& p_WP) const;
  /// Potential of a unit-weight charge at r.
  double unit_potential(const Eigen::Vector3d& p_WP) const;
  /// Both in any precision S, written once: the members above call it with double, the
  /// extended/quad references (precision/) with long double and float128.
  template <typename S>
  void unit_field(const S (&p_WP)[3], S (&f_W)[3], S& potential) const {
    using std::sqrt;
    const S d[3] = {p_WP[0] - p_WM_.x(), p_WP[1] - p_WM_.y(), p_WP[2] - p_WM_.z()};
    const S r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const S z = p_WP[2];
    for (int i = 0; i < 3; ++i) f_W[i] = -alpha_ * d[i] / (r * r * r);
    f_W[2] += beta_ / (z * z);
    potential = -alpha_ / r + beta_ / z;
  }
  const std::vector<Charge>& charges() const { return charges_; }

 private:
  double alpha_;
  double beta_;
  Eigen::Vector3d p_WM_;
  std::vector<Charge> charges_;
};

}  // namespace flexref::core
