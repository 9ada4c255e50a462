#pragma once
/// \file ode_form.hpp
/// The quasi-velocity ODE form y' = f(t, y) of docs/design/model.md, on a flat array for ODE
/// solvers (CVODE, Boost.Odeint). Per body:
///   free  [p_WBr(3) θ(4) v_WBr(3) ω̄(3)]   ṗ = v,  θ̇ = ½ θ ⊗ (0, ω̄),  v̇ = a,  ω̄̇ = α̅
///   pivot [θ(4) ω̄(3)]
///   prescribed []                         (the angle law gives θ, ω̄ at the time of evaluation)
/// followed, for a flexible body, by [q_f(n) q̇_f(n)] with q̇_f' = q̈_f; then the contacts' worn
/// depths h with h' = Model::wear_depth_rates (docs/wear.md; states that the contacts'
/// geometry sees); and last, when the model dissipates, the dissipated work W_d with W_d' =
/// Model::dissipated_power (the energy balance E(t) − E(0) + W_d(t) = work of applied loads is
/// then an output) and the model's extra integrals.
/// The Euler parameters drift off the unit sphere under a generic solver; solvers project
/// them back (normalize_euler_parameters), which is the projection CVODE is given.
#include <cstddef>
#include <span>
#include <vector>

#include "core/model.hpp"
#include "reference/form_layout.hpp"

namespace flexref::reference {

/// How far an ODE reference moves its joints' tracker at an output, from the last solve on its
/// workspace: only the orientation test's reference where that solve kept the tracker's rows
/// (no factorization at each output: on Andrews' squeezer, outputs every 1e-4 s, they would be
/// 300 solves beside the reference's 1 300 evaluations); where it chose rows of its own (the
/// tracker's had become ill-conditioned at its state, or turned through a dependency among
/// themselves), the rows are chosen at the output (TrackerAdvance::kChooseRows).
inline core::TrackerAdvance output_advance(const core::JointMultipliers& last_solve) {
  return last_solve.rows_chosen() ? core::TrackerAdvance::kChooseRows
                                  : core::TrackerAdvance::kReference;
}

class OdeForm {
 public:
  /// `stabilization`: Baumgarte's rate α (1/s) of the ideal joints in the accelerations, for
  /// integrators that cannot project after their steps (core::ModelTpl::
  /// accelerations_from_wrenches): part of the ODE this form is, 0 for the plain index-1 form.
  explicit OdeForm(const core::Model& model, double stabilization = 0.0);

  /// What one evaluation needs besides its arguments (one per thread): scratch space, and the
  /// integrator's joints tracker it reads (core/constraint_tracker.hpp), which the integrator
  /// owns and advances at the states it accepts.
  struct Scratch {
    core::State state;
    core::Workspace workspace;
    core::Accelerations accelerations;
    /// Not owned; nullptr: the rows chosen at the initial configuration (Model::initial_tracker).
    const core::ConstraintTracker* tracker = nullptr;
  };

  int size() const { return size_; }
  const core::Model& model() const { return *model_; }
  double stabilization() const { return stabilization_; }
  /// The tracker the scratch's evaluations read.
  const core::ConstraintTracker& tracker(const Scratch& scratch) const {
    return scratch.tracker != nullptr ? *scratch.tracker : model_->initial_tracker();
  }
  Scratch make_scratch() const;

  /// Packs the state into y, the integrals set to zero.
  void pack(const core::State& state, double* y) const;
  /// Unpacks the state at time t into a state sized for the model (pivot positions are the
  /// fixed pivots; prescribed bodies follow their law at t). θ is
  /// normalized, so loads always see an orthogonal A(θ); θ̇ = ½ θ̂ ⊗ (0, ω̄) is still tangent
  /// to the sphere through the unnormalized y, so |θ| is conserved by the exact flow.
  void unpack(double t, const double* y, core::State& state) const;
  /// ydot = f(t, y); must not allocate.
  void rhs(const core::LoadContext& context, const double* y, double* ydot, Scratch& scratch) const;
  /// Scales every body's θ to unit norm.
  void normalize_euler_parameters(double* y) const;
  /// Ideal joints: projects the bodies' state in y onto Φ = 0 and J v + Φ_t = 0 at t
  /// (core::Model::project, on the scratch's tracker's rows; θ unit); the integrals are left as
  /// they are.
  void project(double t, double* y, Scratch& scratch) const;
  /// Packs the bodies' state and the worn depths into y, the integrals left as they are.
  void pack_bodies(const core::State& state, double* y) const;
  /// Index of the first worn depth in y and their count (Model::wear_depth_count()).
  int depth_index() const { return depth_index_; }
  int depth_count() const { return depth_count_; }
  /// Index of W_d in y, or −1 when not tracked.
  int work_index() const { return work_index_; }
  double dissipated_work(const double* y) const { return work_index_ < 0 ? 0.0 : y[work_index_]; }
  void set_dissipated_work(double* y, double work) const {
    if (work_index_ >= 0) y[work_index_] = work;
  }
  /// The integrals tracked with the state (Model::integral_rates): W_d then the model's extra
  /// integrals (applied work, wear work per contact), from work_index(); 0 when not tracked.
  int integral_count() const { return integral_count_; }
  /// Copies them out of y (integral_count() values) / into y.
  void integrals(const double* y, std::span<double> out) const {
    for (int j = 0; j < integral_count_; ++j) out[static_cast<std::size_t>(j)] = y[work_index_ + j];
  }
  void set_integrals(double* y, std::span<const double> values) const {
    for (int j = 0; j < integral_count_; ++j)
      y[work_index_ + j] = values[static_cast<std::size_t>(j)];
  }

  /// Offsets of the θ blocks in y (bodies that integrate an attitude; for projections).
  const std::vector<int>& theta_offsets() const { return theta_offsets_; }

  /// Offsets of a body's blocks in y (reference/form_layout.hpp, the DAE form's too).
  using Block = BodyBlock;
  const std::vector<Block>& blocks() const { return blocks_; }

 private:
  const core::Model* model_;
  double stabilization_ = 0.0;
  core::State fixed_;  ///< pivot positions
  std::vector<Block> blocks_;
  std::vector<int> theta_offsets_;
  int size_ = 0;
  int depth_index_ = 0;
  int depth_count_ = 0;
  int work_index_ = -1;
  int integral_count_ = 0;
};

}  // namespace flexref::reference
