#pragma once
/// \file dae_form.hpp
/// The Euler-parameter DAE form F(t, y, y') = 0 of design/model.md (paper eq. 19–20), in the
/// stabilized index-2 form of Gear, Gupta and Leimkuhler (1985), for IDA. Per body:
///   free  y = [p(3) θ(4) v(3) v_θ(4) λ μ],  pivot y = [θ(4) v_θ(4) λ μ]
///   ṗ − v = 0
///   θ̇ − v_θ + 2θ μ = 0                         (GGL: C_qᵀ μ with C_q = 2θᵀ)
///   m v̇ − f = 0
///   2Ḡᵀ [ I α̅ + ω̄ × I ω̄ − Aᵀ τ ] + 2θ λ = 0,   ω̄ = 2Ḡ v_θ,  α̅ = 2Ḡ v̇_θ   (θ rows, eq. 19)
///   θᵀ v_θ = 0                                   (velocity constraint, for λ)
///   ½ (θᵀθ − 1) = 0                              (position constraint, for μ)
/// The θ rows are the quasi-velocity rows premultiplied by 2Ḡᵀ (m_θθ = 4ḠᵀIḠ is singular along
/// θ; the constraint row makes the system regular). On a solution λ = μ = 0 exactly (premultiply
/// the θ rows by θᵀ and use Ḡθ = 0): they measure only the discretization's drift.
#include <vector>

#include "core/model.hpp"

namespace flexref::core {

class DaeForm {
 public:
  explicit DaeForm(const Model& model);

  struct Scratch {
    State state;
    Workspace workspace;
  };

  int size() const { return size_; }
  const Model& model() const { return *model_; }
  Scratch make_scratch() const;

  /// Consistent initial values y, y' from a state (λ = μ = 0, y' from the ODE form).
  void initial_values(const LoadContext& context, const State& state, double* y, double* yp) const;
  /// 1 for differential components, 0 for λ and μ (IDASetId).
  std::vector<double> differential_ids() const;
  void residual(const LoadContext& context, const double* y, const double* yp, double* res,
                Scratch& scratch) const;
  /// State at y (θ normalized, ω̄ = 2Ḡ v_θ).
  void unpack(const double* y, State& state) const;

 private:
  const Model* model_;
  State fixed_;
  std::vector<int> offsets_;
  int size_ = 0;
};

}  // namespace flexref::core
