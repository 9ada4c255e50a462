#pragma once
/// \file form_layout.hpp
/// Where each body's state sits in a flat y: the ODE and DAE forms' (reference/ode_form.hpp,
/// reference/dae_form.hpp) and the precision references' (precision/ode_system.hpp), in any
/// scalar type S — one layout for all, so that a Jacobian of the ODE right-hand side serves IDA
/// too (reference/ode_jacobian.hpp). Per body, in model order:
///   free        [p_WBr(3) θ(4) v_WBr(3) ω̄(3) q_f(n) q̇_f(n)]
///   pivot       [θ(4) ω̄(3) q_f(n) q̇_f(n)]
///   prescribed  [q_f(n) q̇_f(n)]   (the angle law gives θ, ω̄ at the time of evaluation)
/// then the contacts' worn depths, and the forms' own components after them.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/model.hpp"

namespace flexref::reference {

/// Offsets of a body's blocks in y (−1 when absent), its mode count and the end of its blocks.
struct BodyBlock {
  int p = -1, theta = -1, v = -1, w = -1, q = -1, qd = -1, n = 0, end = 0;
};

/// The bodies' blocks of a model (core::ModelTpl<S> in any S: the layout is the bodies' motion
/// kinds and mode counts), from y[0]; the last block's end is where the depths start.
template <typename ModelType>
std::vector<BodyBlock> body_blocks(const ModelType& model) {
  std::vector<BodyBlock> blocks;
  int next = 0;
  const auto take = [&next](int count) {
    const int at = next;
    next += count;
    return at;
  };
  for (const auto& b : model.bodies()) {
    BodyBlock k;
    const int n = b.mode_count();
    if (b.is_free()) k.p = take(3);
    if (!b.is_prescribed()) k.theta = take(4);
    if (b.is_free()) k.v = take(3);
    if (!b.is_prescribed()) k.w = take(3);
    k.q = take(n);
    k.qd = take(n);
    k.n = n;
    k.end = next;
    blocks.push_back(k);
  }
  return blocks;
}

/// The bodies' state and the worn depths (at `depth_index`) into y.
template <typename S>
void pack_bodies(const std::vector<BodyBlock>& blocks, int depth_index,
                 const core::StateTpl<S>& state, S* y) {
  using Map3 = Eigen::Map<Eigen::Matrix<S, 3, 1>>;
  using Map4 = Eigen::Map<Eigen::Matrix<S, 4, 1>>;
  using MapX = Eigen::Map<Eigen::Matrix<S, Eigen::Dynamic, 1>>;
  for (std::size_t i = 0; i < state.size(); ++i) {
    const BodyBlock& k = blocks[i];
    const core::BodyStateTpl<S>& s = state[i];
    if (k.p >= 0) Map3(y + k.p) = s.p_WBr;
    if (k.theta >= 0) Map4(y + k.theta) = s.theta_WB;
    if (k.v >= 0) Map3(y + k.v) = s.v_WBr;
    if (k.w >= 0) Map3(y + k.w) = s.w_WB_B;
    MapX(y + k.q, k.n) = s.q_f;
    MapX(y + k.qd, k.n) = s.qd_f;
  }
  MapX(y + depth_index, state.wear_depth.size()) = state.wear_depth;
}

/// The bodies' state and worn depths from y, sized for the model: θ normalized (the loads always
/// see an orthogonal A), a pivot's position `fixed`'s and its velocity zero. A prescribed body's
/// attitude and rates are left to the caller (its angle law at the time: apply_prescribed_motion).
template <typename S>
void unpack_bodies(const std::vector<BodyBlock>& blocks, const core::StateTpl<S>& fixed,
                   int depth_index, const S* y, core::StateTpl<S>& state) {
  using std::sqrt;
  using ConstMap3 = Eigen::Map<const Eigen::Matrix<S, 3, 1>>;
  using ConstMap4 = Eigen::Map<const Eigen::Matrix<S, 4, 1>>;
  using ConstMapX = Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, 1>>;
  for (std::size_t i = 0; i < state.size(); ++i) {
    const BodyBlock& k = blocks[i];
    core::BodyStateTpl<S>& s = state[i];
    if (k.p >= 0) {
      s.p_WBr = ConstMap3(y + k.p);
      s.v_WBr = ConstMap3(y + k.v);
    } else {
      s.p_WBr = fixed[i].p_WBr;
      s.v_WBr.setZero();
    }
    if (k.theta >= 0) {
      s.theta_WB = ConstMap4(y + k.theta);
      const S squared = s.theta_WB.squaredNorm();
      if (squared > S(0)) s.theta_WB /= sqrt(squared);
      s.w_WB_B = ConstMap3(y + k.w);
    }
    s.q_f = ConstMapX(y + k.q, k.n);
    s.qd_f = ConstMapX(y + k.qd, k.n);
  }
  state.wear_depth = ConstMapX(y + depth_index, state.wear_depth.size());
}

/// The state at time t from y (unpack_bodies), prescribed bodies their law's at t.
inline void unpack_bodies(const core::Model& model, const std::vector<BodyBlock>& blocks,
                          const core::State& fixed, int depth_index, double t, const double* y,
                          core::State& state) {
  state.wear_depth.resize(model.wear_depth_count());
  unpack_bodies<double>(blocks, fixed, depth_index, y, state);
  model.apply_prescribed_motion(t, state);
}

}  // namespace flexref::reference
