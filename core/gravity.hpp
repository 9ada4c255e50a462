#pragma once
/// \file gravity.hpp
/// Uniform gravity g_W on every body: f = m g at the centre of mass (docs/design/model.md:
/// Qe_R += m g, Qe_θ += s̃ Aᵀ g), potential V = −Σ m g·p_WBcm.
#include <vector>

#include "core/force_element.hpp"

namespace flexref::core {

class UniformGravity final : public ForceElement {
 public:
  struct BodyMass {
    int body = 0;
    double mass = 0.0;
    Eigen::Vector3d p_BoBcm_B = Eigen::Vector3d::Zero();
  };

  UniformGravity(const Eigen::Vector3d& g_W, std::vector<BodyMass> bodies);
  void add_wrenches(const LoadContext& context, std::span<const BodyKinematics> bodies,
                    std::span<Wrench> wrenches) const override;
  double potential_energy(const LoadContext& context,
                          std::span<const BodyKinematics> bodies) const override;
  std::string describe() const override;
  int max_body_index() const override;
  const Eigen::Vector3d& g_W() const { return g_W_; }

 private:
  Eigen::Vector3d g_W_;
  std::vector<BodyMass> bodies_;
};

}  // namespace flexref::core
