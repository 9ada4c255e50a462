#pragma once
/// \file jacobian_models.hpp
/// Models for the tests of the ODE form's Jacobian and Newton matrix (reference/ode_jacobian,
/// reference/newton_matrix): a free flexible body tethered to a rigid body (loads across
/// bodies, velocity-dependent, dissipating) and a flexible body on a pivot.
#include <algorithm>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/applied_load.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "tests/support/flexible_models.hpp"

namespace flexref::testing {

/// A linear spring–damper between a point of body a and a point of body b (both given from
/// the frame origin): f_a = −k (p_a − p_b) − c (v_a − v_b), f_b = −f_a.
class Tether final : public core::ForceElement {
 public:
  Tether(int a, Eigen::Vector3d p_a, int b, Eigen::Vector3d p_b, double k, double c)
      : a_(a), b_(b), p_a_(std::move(p_a)), p_b_(std::move(p_b)), k_(k), c_(c) {}
  void add_wrenches(const core::LoadContext&, std::span<const core::BodyKinematics> bodies,
                    std::span<core::Wrench> wrenches) const override {
    const core::BodyKinematics& A = bodies[static_cast<std::size_t>(a_)];
    const core::BodyKinematics& B = bodies[static_cast<std::size_t>(b_)];
    const Eigen::Vector3d f =
        -k_ * (A.p_WP(p_a_) - B.p_WP(p_b_)) - c_ * (A.v_WP(p_a_) - B.v_WP(p_b_));
    wrenches[static_cast<std::size_t>(a_)].add_force_at(f, A.p_BrP_W(p_a_));
    wrenches[static_cast<std::size_t>(b_)].add_force_at(-f, B.p_BrP_W(p_b_));
  }
  double dissipated_power(const core::LoadContext&,
                          std::span<const core::BodyKinematics> bodies) const override {
    const core::BodyKinematics& A = bodies[static_cast<std::size_t>(a_)];
    const core::BodyKinematics& B = bodies[static_cast<std::size_t>(b_)];
    return c_ * (A.v_WP(p_a_) - B.v_WP(p_b_)).squaredNorm();
  }
  bool depends_on_velocity() const override { return true; }
  int max_body_index() const override { return std::max(a_, b_); }
  std::string describe() const override { return "tether"; }

 private:
  int a_, b_;
  Eigen::Vector3d p_a_, p_b_;
  double k_, c_;
};

/// flexible_spinner (8 modes, ζ = 0.02) tethered to a free rigid block, with gravity on both.
inline core::Model spinner_and_block(core::FlexibleFormulation formulation) {
  const core::Model base = testing::flexible_spinner_model(formulation, 8, 10);
  core::RigidBodyDescription spinner = base.body(0).description();
  spinner.flexible->modal.damping_ratio.setConstant(0.02);
  core::RigidBodyDescription block;
  block.name = "block";
  block.mass = 2.0;
  block.I_Bcm_B = Eigen::Vector3d(0.3, 0.4, 0.5).asDiagonal();
  block.initial.p_WBo = Eigen::Vector3d(1.5, 0.2, 0.0);
  std::vector<core::Body> bodies{core::Body(spinner), core::Body(block)};
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(0.0, 0.0, 5.0), core::LoadFrame::kWorld,
      core::TimeProfile::sin2_pulse(0.0, 0.5)));
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0.3, -0.2, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, bodies[0].mass(), spinner.p_BoBcm_B},
                                                  {1, 2.0, Eigen::Vector3d::Zero()}}));
  elements.push_back(std::make_unique<Tether>(0, Eigen::Vector3d(0.0, 0.1, 0.0), 1,
                                              Eigen::Vector3d(0.1, 0.0, 0.05), 40.0, 3.0));
  return core::Model(std::move(bodies), std::move(elements), formulation);
}

/// The spinner's body on a pivot at its hub's rim, under gravity (6 modes).
inline core::Model pivot_spinner(core::FlexibleFormulation formulation) {
  const core::Model base = testing::flexible_spinner_model(formulation, 6, 10);
  core::RigidBodyDescription d = base.body(0).description();
  d.motion = core::MotionKind::kPivot;
  d.p_BoPivot_B = Eigen::Vector3d(-0.05, 0.02, 0.1);
  d.initial.v_WBo.setZero();
  std::vector<core::Body> bodies{core::Body(d)};
  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0.0, 0.0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, bodies[0].mass(), d.p_BoBcm_B}}));
  return core::Model(std::move(bodies), std::move(elements), formulation);
}

}  // namespace flexref::testing
