#include "reference/ode_form.hpp"

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

OdeForm::Block OdeForm::block_of(const core::Body& b, int offset) {
  Block k;
  const int n = b.mode_count();
  int next = offset;
  if (b.is_free()) {
    k.p = next;
    next += 3;
  }
  if (!b.is_prescribed()) {
    k.theta = next;
    next += 4;
  }
  if (b.is_free()) {
    k.v = next;
    next += 3;
  }
  if (!b.is_prescribed()) {
    k.w = next;
    next += 3;
  }
  k.q = next;
  k.qd = next + n;
  k.n = n;
  k.end = next + 2 * n;
  return k;
}

OdeForm::OdeForm(const core::Model& model, double stabilization)
    : model_(&model), stabilization_(stabilization), fixed_(model.initial_state()) {
  for (const core::Body& b : model.bodies()) {
    const Block k = block_of(b, size_);
    blocks_.push_back(k);
    if (k.theta >= 0) theta_offsets_.push_back(k.theta);
    size_ = k.end;
  }
  depth_index_ = size_;
  depth_count_ = model.wear_depth_count();
  size_ += depth_count_;
  if (model.tracks_work()) {
    work_index_ = size_;
    integral_count_ = 1 + model.extra_integral_count();
    size_ += integral_count_;
  }
}

OdeForm::Scratch OdeForm::make_scratch() const {
  Scratch s;
  s.state = fixed_;
  s.workspace = model_->make_workspace();
  s.accelerations = model_->make_accelerations();
  return s;
}

void OdeForm::pack(const core::State& state, double* y) const {
  pack_bodies(state, y);
  for (int j = 0; j < integral_count_; ++j) y[work_index_ + j] = 0.0;
}

void OdeForm::pack_bodies(const core::State& state, double* y) const {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    const core::BodyState& s = state[i];
    if (k.p >= 0) Map3(y + k.p) = s.p_WBr;
    if (k.theta >= 0) Map4(y + k.theta) = s.theta_WB;
    if (k.v >= 0) Map3(y + k.v) = s.v_WBr;
    if (k.w >= 0) Map3(y + k.w) = s.w_WB_B;
    MapX(y + k.q, k.n) = s.q_f;
    MapX(y + k.qd, k.n) = s.qd_f;
  }
  MapX(y + depth_index_, depth_count_) = state.wear_depth;
}

void OdeForm::unpack(double t, const double* y, core::State& state) const {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    core::BodyState& s = state[i];
    if (k.p >= 0) {
      s.p_WBr = ConstMap3(y + k.p);
      s.v_WBr = ConstMap3(y + k.v);
    } else {
      s.p_WBr = fixed_[i].p_WBr;
      s.v_WBr.setZero();
    }
    if (k.theta >= 0) {
      s.theta_WB = ConstMap4(y + k.theta).normalized();
      s.w_WB_B = ConstMap3(y + k.w);
    }
    s.q_f = ConstMapX(y + k.q, k.n);
    s.qd_f = ConstMapX(y + k.qd, k.n);
  }
  state.wear_depth = ConstMapX(y + depth_index_, depth_count_);
  model_->apply_prescribed_motion(t, state);
}

void OdeForm::rhs(const core::LoadContext& context, const double* y, double* ydot,
                  Scratch& scratch) const {
  unpack(context.t, y, scratch.state);
  model_->compute_accelerations(context, scratch.state, tracker(scratch), scratch.workspace,
                                scratch.accelerations, stabilization_);
  for (std::size_t i = 0; i < scratch.state.size(); ++i) {
    const Block& k = blocks_[i];
    const core::BodyState& s = scratch.state[i];
    const core::BodyAcceleration& a = scratch.accelerations[i];
    if (k.p >= 0) {
      Map3(ydot + k.p) = s.v_WBr;  // ṗ = v
      Map3(ydot + k.v) = a.a_WBr;  // v̇ = a
    }
    if (k.theta >= 0) {
      // θ̇ = ½ θ ⊗ (0, ω̄), with the unnormalized θ of y (tangent to its sphere)
      Map4(ydot + k.theta) = rotation::euler_parameter_rate(ConstMap4(y + k.theta), s.w_WB_B);
      Map3(ydot + k.w) = a.alpha_WB_B;  // ω̄̇ = α̅
    }
    MapX(ydot + k.q, k.n) = s.qd_f;    // q̇_f
    MapX(ydot + k.qd, k.n) = a.qdd_f;  // q̈_f
  }
  if (depth_count_ > 0) {
    // h' = the contacts' wear rates at the same state
    model_->wear_depth_rates(
        context, scratch.state, scratch.workspace,
        std::span<double>(ydot + depth_index_, static_cast<std::size_t>(depth_count_)));
  }
  if (work_index_ >= 0) {
    // W_d' = dissipated power at the same state, and the extra integrals' rates
    // The drives' power from the constrained solve just made at this state.
    model_->integral_rates(
        context, scratch.state, scratch.workspace,
        std::span<double>(ydot + work_index_, static_cast<std::size_t>(integral_count_)),
        &model_->joint_multipliers(scratch.workspace).force());
  }
}

void OdeForm::project(double t, double* y, Scratch& scratch) const {
  if (!model_->has_constraints()) {
    normalize_euler_parameters(y);
    return;
  }
  unpack(t, y, scratch.state);
  model_->project(t, scratch.state, tracker(scratch), scratch.workspace);
  pack_bodies(scratch.state, y);
}

void OdeForm::normalize_euler_parameters(double* y) const {
  for (int offset : theta_offsets_) {
    Map4 theta(y + offset);
    theta /= theta.norm();
  }
}

}  // namespace flexref::reference
