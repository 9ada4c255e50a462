#include "reference/dae_form.hpp"

#include <algorithm>
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

DaeForm::Block DaeForm::block_of(const core::Body& b, int offset) {
  Block k;
  const int n = b.mode_count();
  int next = offset;
  auto take = [&next](int count) {
    const int at = next;
    next += count;
    return at;
  };
  if (b.is_free()) k.p = take(3);
  if (!b.is_prescribed()) k.theta = take(4);
  if (b.is_free()) k.v = take(3);
  if (!b.is_prescribed()) k.v_theta = take(4);
  k.q = take(n);
  k.v_q = take(n);
  if (!b.is_prescribed()) {
    k.lambda = take(1);
    k.mu = take(1);
  }
  k.n = n;
  k.end = next;
  return k;
}

DaeForm::DaeForm(const core::Model& model) : model_(&model), fixed_(model.initial_state()) {
  for (const core::Body& b : model.bodies()) {
    const Block k = block_of(b, size_);
    blocks_.push_back(k);
    size_ = k.end;
    max_rows_ = std::max(max_rows_, 6 + k.n);
  }
  if (model.dissipates()) work_index_ = size_++;
}

DaeForm::Scratch DaeForm::make_scratch() const {
  Scratch s;
  s.state = fixed_;
  s.workspace = model_->make_workspace();
  s.accelerations = model_->make_accelerations();
  s.residual = Eigen::VectorXd::Zero(max_rows_);
  return s;
}

std::vector<double> DaeForm::differential_ids() const {
  std::vector<double> ids(static_cast<std::size_t>(size_), 1.0);
  for (const Block& k : blocks_) {
    if (k.lambda >= 0) ids[static_cast<std::size_t>(k.lambda)] = 0.0;
    if (k.mu >= 0) ids[static_cast<std::size_t>(k.mu)] = 0.0;
  }
  return ids;
}

void DaeForm::initial_values(const core::LoadContext& context, const core::State& state, double* y,
                             double* yp) const {
  core::Workspace ws = model_->make_workspace();
  core::Accelerations acc = model_->make_accelerations();
  model_->compute_accelerations(context, state, ws, acc);
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    const core::BodyState& s = state[i];
    if (k.p >= 0) {
      Map3(y + k.p) = s.p_WBr;
      Map3(y + k.v) = s.v_WBr;
      Map3(yp + k.p) = s.v_WBr;
      Map3(yp + k.v) = acc[i].a_WBr;
    }
    if (k.theta >= 0) {
      const rotation::EulerParameters theta_dot =
          rotation::euler_parameter_rate(s.theta_WB, s.w_WB_B);
      // θ̈ = −¼|ω̄|² θ + ½ θ ⊗ (0, α̅)
      const rotation::EulerParameters theta_ddot =
          -0.25 * s.w_WB_B.squaredNorm() * s.theta_WB +
          rotation::euler_parameter_rate(s.theta_WB, acc[i].alpha_WB_B);
      Map4(y + k.theta) = s.theta_WB;
      Map4(y + k.v_theta) = theta_dot;
      Map4(yp + k.theta) = theta_dot;
      Map4(yp + k.v_theta) = theta_ddot;
      y[k.lambda] = y[k.mu] = 0.0;
      yp[k.lambda] = yp[k.mu] = 0.0;
    }
    MapX(y + k.q, k.n) = s.q_f;
    MapX(y + k.v_q, k.n) = s.qd_f;
    MapX(yp + k.q, k.n) = s.qd_f;
    MapX(yp + k.v_q, k.n) = acc[i].qdd_f;
  }
  if (work_index_ >= 0) {
    y[work_index_] = 0.0;
    yp[work_index_] = model_->dissipated_power(context, state, ws);
  }
}

void DaeForm::unpack(double t, const double* y, core::State& state) const {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    core::BodyState& s = state[i];
    if (k.theta >= 0) {
      const rotation::EulerParameters theta = ConstMap4(y + k.theta);
      s.theta_WB = theta.normalized();
      // For θ = s θ̂ off the sphere, Ḡ(θ) θ̇ = s² Ḡ(θ̂) θ̂̇: divide by |θ|² so ω̄ is exact.
      s.w_WB_B =
          2.0 * rotation::g_bar_matrix(theta) * ConstMap4(y + k.v_theta) / theta.squaredNorm();
    }
    if (k.p >= 0) {
      s.p_WBr = ConstMap3(y + k.p);
      s.v_WBr = ConstMap3(y + k.v);
    } else {
      s.p_WBr = fixed_[i].p_WBr;
      s.v_WBr.setZero();
    }
    s.q_f = ConstMapX(y + k.q, k.n);
    s.qd_f = ConstMapX(y + k.v_q, k.n);
  }
  model_->apply_prescribed_motion(t, state);
}

void DaeForm::residual(const core::LoadContext& context, const double* y, const double* yp,
                       double* res, Scratch& scratch) const {
  // Loads at the current iterate. θ enters A(θ) unnormalized here: the residual is that of
  // eq. 19 exactly as written, and the constraint row keeps θ on the sphere.
  core::State& state = scratch.state;
  core::Accelerations& acc = scratch.accelerations;
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    core::BodyState& s = state[i];
    if (k.theta >= 0) {
      s.theta_WB = ConstMap4(y + k.theta);
      s.w_WB_B = 2.0 * rotation::g_bar_matrix(s.theta_WB) * ConstMap4(y + k.v_theta);
      acc[i].alpha_WB_B =
          2.0 * rotation::g_bar_matrix(s.theta_WB) * ConstMap4(yp + k.v_theta);  // α̅ = 2Ḡ v̇_θ
    }
    if (k.p >= 0) {
      s.p_WBr = ConstMap3(y + k.p);
      s.v_WBr = ConstMap3(y + k.v);
      acc[i].a_WBr = ConstMap3(yp + k.v);
    }
    s.q_f = ConstMapX(y + k.q, k.n);
    s.qd_f = ConstMapX(y + k.v_q, k.n);
    acc[i].qdd_f = ConstMapX(yp + k.v_q, k.n);
  }
  model_->apply_prescribed_motion(context.t, state);
  model_->compute_wrenches(context, state, scratch.workspace);
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    const core::Body& b = model_->body(static_cast<int>(i));
    auto r = scratch.residual.head(6 + k.n);
    if (b.is_prescribed()) {
      // Known rigid accelerations of the law (the rigid rows are the drive's reactions).
      acc[i].a_WBr.setZero();
      const core::RigidBodyDescription& d = b.description();
      acc[i].alpha_WB_B =
          prescribed_attitude(d.prescribed, d.initial.theta_WB, context.t).alpha_WB_B;
    } else if (k.p < 0) {
      acc[i].a_WBr.setZero();  // pivot
    }
    model_->dynamics_residual(static_cast<int>(i), state[i], acc[i], scratch.workspace, r);
    if (k.p >= 0) {
      Map3(res + k.p) = ConstMap3(yp + k.p) - state[i].v_WBr;  // ṗ − v
      Map3(res + k.v) = r.head<3>();                           // m v̇ − f (+ coupling)
    }
    if (k.theta >= 0) {
      const rotation::EulerParameters theta = ConstMap4(y + k.theta);
      const rotation::EulerParameters v_theta = ConstMap4(y + k.v_theta);
      Map4(res + k.theta) = ConstMap4(yp + k.theta) - v_theta + 2.0 * y[k.mu] * theta;  // GGL
      // θ rows: 2Ḡᵀ (rotation rows) + 2θ λ   (eq. 19)
      Map4(res + k.v_theta) = 2.0 * rotation::g_bar_matrix(theta).transpose() * r.segment<3>(3) +
                              2.0 * y[k.lambda] * theta;
      res[k.lambda] = theta.dot(v_theta);             // velocity constraint
      res[k.mu] = 0.5 * (theta.squaredNorm() - 1.0);  // position constraint
    }
    MapX(res + k.q, k.n) = ConstMapX(yp + k.q, k.n) - ConstMapX(y + k.v_q, k.n);  // q̇ − v_q
    MapX(res + k.v_q, k.n) = r.tail(k.n);                                         // modal rows
  }
  if (work_index_ >= 0) {
    // W_d' − P = 0
    res[work_index_] =
        yp[work_index_] - model_->dissipated_power(context, state, scratch.workspace);
  }
}

}  // namespace flexref::reference
