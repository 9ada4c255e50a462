#include "reference/form_layout.hpp"

#include <cstddef>

namespace flexref::reference {

namespace {

using ConstMap3 = Eigen::Map<const Eigen::Vector3d>;
using ConstMap4 = Eigen::Map<const Eigen::Vector4d>;
using ConstMapX = Eigen::Map<const Eigen::VectorXd>;
using Map3 = Eigen::Map<Eigen::Vector3d>;
using Map4 = Eigen::Map<Eigen::Vector4d>;
using MapX = Eigen::Map<Eigen::VectorXd>;

}  // namespace

std::vector<BodyBlock> body_blocks(const core::Model& model) {
  std::vector<BodyBlock> blocks;
  int next = 0;
  const auto take = [&next](int count) {
    const int at = next;
    next += count;
    return at;
  };
  for (const core::Body& b : model.bodies()) {
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

void pack_bodies(const std::vector<BodyBlock>& blocks, int depth_index, const core::State& state,
                 double* y) {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const BodyBlock& k = blocks[i];
    const core::BodyState& s = state[i];
    if (k.p >= 0) Map3(y + k.p) = s.p_WBr;
    if (k.theta >= 0) Map4(y + k.theta) = s.theta_WB;
    if (k.v >= 0) Map3(y + k.v) = s.v_WBr;
    if (k.w >= 0) Map3(y + k.w) = s.w_WB_B;
    MapX(y + k.q, k.n) = s.q_f;
    MapX(y + k.qd, k.n) = s.qd_f;
  }
  MapX(y + depth_index, state.wear_depth.size()) = state.wear_depth;
}

void unpack_bodies(const core::Model& model, const std::vector<BodyBlock>& blocks,
                   const core::State& fixed, int depth_index, double t, const double* y,
                   core::State& state) {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const BodyBlock& k = blocks[i];
    core::BodyState& s = state[i];
    if (k.p >= 0) {
      s.p_WBr = ConstMap3(y + k.p);
      s.v_WBr = ConstMap3(y + k.v);
    } else {
      s.p_WBr = fixed[i].p_WBr;
      s.v_WBr.setZero();
    }
    if (k.theta >= 0) {
      s.theta_WB = ConstMap4(y + k.theta).normalized();
      s.w_WB_B = ConstMap3(y + k.w);
    }
    s.q_f = ConstMapX(y + k.q, k.n);
    s.qd_f = ConstMapX(y + k.qd, k.n);
  }
  state.wear_depth = ConstMapX(y + depth_index, model.wear_depth_count());
  model.apply_prescribed_motion(t, state);
}

}  // namespace flexref::reference
