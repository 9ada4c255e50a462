#pragma once
/// \file c2.hpp
/// ALGO C2 of Simo & Wong (1991), explicit (Newmark β = 0, γ = 1), as the paper implements it
/// (docs/design/schemes.md), combined with central differences for the translation of free bodies
/// (the paper's hybrid step):
///   x_{n+1} = x_n + h v_n + ½ h² a_n
///   Θ = h (W_n + ½ h A_n),   R_{n+1} = R_n exp(Θ̃)
///   loads at the new configuration (one evaluation): f_{n+1}, Γ_{n+1}
///   v_{n+1} = v_n + ½ h (a_n + a_{n+1}),   a = f/m
///   J W_{n+1} = R_{n+1}ᵀ [ R_n J W_n + (h/2)(Γ_n + Γ_{n+1}) ]
///   A_{n+1} = (W_{n+1} − W_n)/h
/// Rotation about Br with I_Br (Br = centre of mass of a free body, the pivot of a pivot body).
/// Conserves π = R J W exactly (to round-off) when torque-free; not the energy.
///
/// Velocity-dependent loads are evaluated at the predicted velocities v_n + h a_n and
/// W_n + h A_n (explicit Euler predictors; the evaluation is at t_{n+1}, before v_{n+1} and
/// W_{n+1} are known). A_0 is the true angular acceleration from the Euler equation at t0.
/// When t_n is a known load discontinuity, the carried loads Γ_n and a_n are left limits and
/// are re-evaluated at t_n on the new segment; A_n, a backward difference of W and not a
/// load, takes the jump the load jump implies, A_n += J⁻¹ R_nᵀ (Γ_n⁺ − Γ_n⁻) (nothing changes
/// for a body whose loads are continuous, so bodies stay independent).
#include <Eigen/Core>
#include <vector>

#include "lie/stepper.hpp"
#include "lie/wear_depth_update.hpp"

namespace flexref::lie {

class C2Stepper final : public Stepper {
 public:
  /// The model must outlive the stepper.
  explicit C2Stepper(const core::Model& model);

  std::string_view name() const override { return "c2"; }
  int order() const override { return 2; }
  /// One per step, plus one at the first step and at each step starting on a discontinuity.
  double force_evaluations_per_step() const override { return 1.0; }

  void initialize(double t0, const core::State& state) override;
  StepStatus step(double h) override;

  double time() const override { return time_; }
  const core::State& state() const override { return state_; }
  /// Advances the contacts' worn depths (lie/wear_depth_update.hpp).
  bool integrates_wear_depth() const override { return true; }
  /// a_n (world) and A_n (body), the Newmark accelerations carried by the scheme.
  const core::Accelerations& accelerations() const { return acc_; }

 private:
  /// Γ_n and a_n (and A_0 at the first step) from the loads at t_n on the segment of the
  /// step [t_n, t_n + h].
  void restart(double h);

  const core::Model& model_;
  double time_ = 0.0;
  bool restart_pending_ = true;
  core::State state_;                             ///< step n
  core::State next_;                              ///< step n + 1 while it is computed
  core::Accelerations acc_;                       ///< a_n, A_n
  core::Accelerations acc_next_;                  ///< a_{n+1}, A_{n+1}
  std::vector<Eigen::Vector3d> torque_W_;         ///< Γ_n about Br (world)
  std::vector<Eigen::Vector3d> torque_next_W_;    ///< Γ_{n+1}
  std::vector<Eigen::Vector3d> momentum_W_;       ///< π_n = R_n J W_n about Br (world)
  std::vector<Eigen::Vector3d> momentum_next_W_;  ///< π_{n+1}
  core::Workspace ws_;
  detail::WearDepthUpdate wear_;  ///< the worn depths' rates
};

}  // namespace flexref::lie
