#pragma once
/// \file model.hpp
/// The immutable model every integrator sees (Pinocchio's Model/Data split): bodies and
/// force elements, and the one narrow interface integrators use — loads, accelerations,
/// energy and momentum at a state. Scratch space lives in a separate Workspace, so no
/// evaluation allocates.
///
/// Equations (design/model.md, quasi-velocity form, rigid bodies about Br):
///   free:  m a_WBr = f_W,                  I_Br α̅ + ω̄ × I_Br ω̄ = Aᵀ τ_Br_W
///   pivot: a_WBr = 0,                      I_Pv α̅ + ω̄ × I_Pv ω̄ = Aᵀ τ_Pv_W
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/body.hpp"
#include "core/force_element.hpp"
#include "core/state.hpp"

namespace flexref::core {

/// Per-evaluation scratch space; make one per thread with Model::make_workspace().
struct Workspace {
  std::vector<BodyKinematics> kinematics;
  std::vector<Wrench> wrenches;
};

class Model {
 public:
  Model(std::vector<Body> bodies, std::vector<std::unique_ptr<const ForceElement>> elements);

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  const Body& body(int i) const { return bodies_[static_cast<std::size_t>(i)]; }
  const std::vector<Body>& bodies() const { return bodies_; }
  std::span<const std::unique_ptr<const ForceElement>> elements() const { return elements_; }
  /// Index of the body with this name, or −1.
  int body_index(const std::string& name) const;

  /// Sorted, unique known times where loads switch (time-profile ends).
  const std::vector<double>& discontinuities() const { return discontinuities_; }
  /// True when some element depends on velocities.
  bool has_velocity_dependent_loads() const { return velocity_dependent_; }

  State initial_state() const;
  Workspace make_workspace() const;

  /// Fills workspace.kinematics (A(θ) per body) and workspace.wrenches.
  void compute_wrenches(const LoadContext& context, const State& state, Workspace& ws) const;
  /// Accelerations from the loads already in ws.wrenches (see compute_wrenches).
  void accelerations_from_wrenches(const State& state, const Workspace& ws,
                                   Accelerations& accelerations) const;
  /// compute_wrenches then accelerations_from_wrenches.
  void compute_accelerations(const LoadContext& context, const State& state, Workspace& ws,
                             Accelerations& accelerations) const;

  double kinetic_energy(const State& state) const;
  double potential_energy(const LoadContext& context, const State& state, Workspace& ws) const;
  /// Total linear momentum, world.
  Eigen::Vector3d linear_momentum_W(const State& state) const;
  /// Total angular momentum about the world origin, world.
  Eigen::Vector3d angular_momentum_W(const State& state) const;

  /// Frame origin Bo of body i (the CSV's B.x, B.y, B.z) and its velocity.
  Eigen::Vector3d p_WBo(int i, const BodyState& s) const;
  Eigen::Vector3d v_WBo(int i, const BodyState& s) const;
  /// World position of a body point given from the frame origin.
  Eigen::Vector3d p_WP(int i, const BodyState& s, const Eigen::Vector3d& p_BoP_B) const;

 private:
  std::vector<Body> bodies_;
  std::vector<std::unique_ptr<const ForceElement>> elements_;
  std::vector<double> discontinuities_;
  bool velocity_dependent_ = false;
};

}  // namespace flexref::core
