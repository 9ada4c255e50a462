#pragma once
/// \file ode_form.hpp
/// The quasi-velocity ODE form y' = f(t, y) of design/model.md, on a flat array for ODE
/// solvers (CVODE, Boost.Odeint). Per body:
///   free  [p_WBr(3) θ(4) v_WBr(3) ω̄(3)]   ṗ = v,  θ̇ = ½ θ ⊗ (0, ω̄),  v̇ = a,  ω̄̇ = α̅
///   pivot [θ(4) ω̄(3)]
/// The Euler parameters drift off the unit sphere under a generic solver; solvers project
/// them back (normalize_euler_parameters), which is the projection CVODE is given.
#include <vector>

#include "core/model.hpp"

namespace flexref::core {

class OdeForm {
 public:
  explicit OdeForm(const Model& model);

  /// Scratch space of one evaluation (one per thread).
  struct Scratch {
    State state;
    Workspace workspace;
    Accelerations accelerations;
  };

  int size() const { return size_; }
  const Model& model() const { return *model_; }
  Scratch make_scratch() const;

  void pack(const State& state, double* y) const;
  /// Unpacks into a state sized for the model (pivot positions are the fixed pivots). θ is
  /// normalized, so loads always see an orthogonal A(θ); θ̇ = ½ θ̂ ⊗ (0, ω̄) is still tangent
  /// to the sphere through the unnormalized y, so |θ| is conserved by the exact flow.
  void unpack(const double* y, State& state) const;
  /// ydot = f(t, y); must not allocate.
  void rhs(const LoadContext& context, const double* y, double* ydot, Scratch& scratch) const;
  /// Scales every body's θ to unit norm.
  void normalize_euler_parameters(double* y) const;
  /// Offsets of each body's θ block in y (for projections and error weights).
  const std::vector<int>& theta_offsets() const { return theta_offsets_; }

 private:
  const Model* model_;
  State fixed_;  ///< pivot positions
  std::vector<int> offsets_;
  std::vector<int> theta_offsets_;
  int size_ = 0;
};

}  // namespace flexref::core
