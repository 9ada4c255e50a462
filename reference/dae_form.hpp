#pragma once
/// \file dae_form.hpp
/// The Euler-parameter DAE form F(t, y, y') = 0 of docs/design/model.md (paper eq. 19–20), in the
/// stabilized index-2 form of Gear, Gupta and Leimkuhler (1985), for IDA. Per body:
///   free  y = [p(3) θ(4) v(3) v_θ(4) q(n) v_q(n) λ μ],  pivot y = [θ(4) v_θ(4) q v_q λ μ],
///   prescribed y = [q(n) v_q(n)]   (q, v_q only for a flexible body)
///   ṗ − v = 0
///   θ̇ − v_θ + 2θ μ = 0                         (GGL: C_qᵀ μ with C_q = 2θᵀ)
///   q̇ − v_q = 0
///   m v̇ − f = 0                                 (a flexible body: the rows of Model::
///   2Ḡᵀ [ I α̅ + ω̄ × I ω̄ − Aᵀ τ ] + 2θ λ = 0      dynamics_residual, M v − Q, translation,
///   (modal rows)                                 2Ḡᵀ·rotation, modes; ω̄ = 2Ḡ v_θ, α̅ = 2Ḡ v̇_θ)
///   θᵀ v_θ = 0                                   (velocity constraint, for λ)
///   ½ (θᵀθ − 1) = 0                              (position constraint, for μ)
/// The θ rows are the quasi-velocity rows premultiplied by 2Ḡᵀ (m_θθ = 4ḠᵀIḠ is singular along
/// θ; the constraint row makes the system regular). On a solution λ = μ = 0 exactly (premultiply
/// the θ rows by θᵀ and use Ḡθ = 0): they measure only the discretization's drift.
#include <vector>

#include "core/model.hpp"

namespace flexref::reference {

class DaeForm {
 public:
  explicit DaeForm(const core::Model& model);

  struct Scratch {
    core::State state;
    core::Workspace workspace;
    core::Accelerations accelerations;
    Eigen::VectorXd residual;
  };

  int size() const { return size_; }
  const core::Model& model() const { return *model_; }
  Scratch make_scratch() const;

  /// Consistent initial values y, y' from a state (λ = μ = 0, y' from the ODE form).
  void initial_values(const core::LoadContext& context, const core::State& state, double* y,
                      double* yp) const;
  /// 1 for differential components, 0 for λ and μ (IDASetId).
  std::vector<double> differential_ids() const;
  void residual(const core::LoadContext& context, const double* y, const double* yp, double* res,
                Scratch& scratch) const;
  /// State at time t and y (θ normalized, ω̄ = 2Ḡ v_θ; prescribed bodies follow their law).
  void unpack(double t, const double* y, core::State& state) const;

  /// Index of the dissipated work W_d in y (differential, W_d' = dissipated power), or −1.
  int work_index() const { return work_index_; }
  double dissipated_work(const double* y) const { return work_index_ < 0 ? 0.0 : y[work_index_]; }
  /// Sets W_d in y (the initial values set it to 0).
  void set_dissipated_work(double* y, double work) const {
    if (work_index_ >= 0) y[work_index_] = work;
  }

  /// Offsets of a body's blocks in y (−1 when absent) and its mode count.
  struct Block {
    int p = -1, theta = -1, v = -1, v_theta = -1, q = -1, v_q = -1, lambda = -1, mu = -1;
    int n = 0, end = 0;
  };
  const std::vector<Block>& blocks() const { return blocks_; }

 private:
  static Block block_of(const core::Body& b, int offset);

  const core::Model* model_;
  core::State fixed_;
  std::vector<Block> blocks_;
  int size_ = 0;
  int max_rows_ = 6;
  int work_index_ = -1;
};

}  // namespace flexref::reference
