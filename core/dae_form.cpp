#include "core/dae_form.hpp"

#include <cstddef>

namespace flexref::core {
namespace {

using ConstMap3 = Eigen::Map<const Eigen::Vector3d>;
using ConstMap4 = Eigen::Map<const Eigen::Vector4d>;
using Map3 = Eigen::Map<Eigen::Vector3d>;
using Map4 = Eigen::Map<Eigen::Vector4d>;

// Offsets inside a body's block: translation (free only) comes first.
struct Block {
  int p, theta, v, v_theta, lambda, mu;
};

Block block(bool free) {
  if (free) return {0, 3, 7, 10, 14, 15};
  return {-1, 0, -1, 4, 8, 9};
}

}  // namespace

DaeForm::DaeForm(const Model& model) : model_(&model), fixed_(model.initial_state()) {
  for (const Body& b : model.bodies()) {
    offsets_.push_back(size_);
    size_ += b.is_free() ? 16 : 10;
  }
}

DaeForm::Scratch DaeForm::make_scratch() const {
  Scratch s;
  s.state = fixed_;
  s.workspace = model_->make_workspace();
  return s;
}

std::vector<double> DaeForm::differential_ids() const {
  std::vector<double> ids(static_cast<std::size_t>(size_), 1.0);
  for (std::size_t i = 0; i < offsets_.size(); ++i) {
    const Block k = block(model_->body(static_cast<int>(i)).is_free());
    ids[static_cast<std::size_t>(offsets_[i] + k.lambda)] = 0.0;
    ids[static_cast<std::size_t>(offsets_[i] + k.mu)] = 0.0;
  }
  return ids;
}

void DaeForm::initial_values(const LoadContext& context, const State& state, double* y,
                             double* yp) const {
  Workspace ws = model_->make_workspace();
  Accelerations acc(state.size());
  model_->compute_accelerations(context, state, ws, acc);
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block k = block(model_->body(static_cast<int>(i)).is_free());
    double* yi = y + offsets_[i];
    double* ypi = yp + offsets_[i];
    const BodyState& s = state[i];
    const EulerParameters theta_dot = euler_parameter_rate(s.theta_WB, s.w_WB_B);
    // θ̈ = −¼|ω̄|² θ + ½ θ ⊗ (0, α̅)
    const EulerParameters theta_ddot = -0.25 * s.w_WB_B.squaredNorm() * s.theta_WB +
                                       euler_parameter_rate(s.theta_WB, acc[i].alpha_WB_B);
    if (k.p >= 0) {
      Map3(yi + k.p) = s.p_WBr;
      Map3(yi + k.v) = s.v_WBr;
      Map3(ypi + k.p) = s.v_WBr;
      Map3(ypi + k.v) = acc[i].a_WBr;
    }
    Map4(yi + k.theta) = s.theta_WB;
    Map4(yi + k.v_theta) = theta_dot;
    Map4(ypi + k.theta) = theta_dot;
    Map4(ypi + k.v_theta) = theta_ddot;
    yi[k.lambda] = yi[k.mu] = 0.0;
    ypi[k.lambda] = ypi[k.mu] = 0.0;
  }
}

void DaeForm::unpack(const double* y, State& state) const {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block k = block(model_->body(static_cast<int>(i)).is_free());
    const double* yi = y + offsets_[i];
    BodyState& s = state[i];
    const EulerParameters theta = ConstMap4(yi + k.theta);
    s.theta_WB = theta.normalized();
    // For θ = s θ̂ off the sphere, Ḡ(θ) θ̇ = s² Ḡ(θ̂) θ̂̇: divide by |θ|² so ω̄ is exact.
    s.w_WB_B = 2.0 * g_bar_matrix(theta) * ConstMap4(yi + k.v_theta) / theta.squaredNorm();
    if (k.p >= 0) {
      s.p_WBr = ConstMap3(yi + k.p);
      s.v_WBr = ConstMap3(yi + k.v);
    } else {
      s.p_WBr = fixed_[i].p_WBr;
      s.v_WBr.setZero();
    }
  }
}

void DaeForm::residual(const LoadContext& context, const double* y, const double* yp, double* res,
                       Scratch& scratch) const {
  // Loads at the current iterate. θ enters A(θ) unnormalized here: the residual is that of
  // eq. 19 exactly as written, and the constraint row keeps θ on the sphere.
  State& state = scratch.state;
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block k = block(model_->body(static_cast<int>(i)).is_free());
    const double* yi = y + offsets_[i];
    BodyState& s = state[i];
    s.theta_WB = ConstMap4(yi + k.theta);
    s.w_WB_B = 2.0 * g_bar_matrix(s.theta_WB) * ConstMap4(yi + k.v_theta);
    if (k.p >= 0) {
      s.p_WBr = ConstMap3(yi + k.p);
      s.v_WBr = ConstMap3(yi + k.v);
    }
  }
  model_->compute_wrenches(context, state, scratch.workspace);

  for (std::size_t i = 0; i < state.size(); ++i) {
    const Body& b = model_->body(static_cast<int>(i));
    const Block k = block(b.is_free());
    const double* yi = y + offsets_[i];
    const double* ypi = yp + offsets_[i];
    double* ri = res + offsets_[i];
    const BodyState& s = state[i];
    const Wrench& w = scratch.workspace.wrenches[i];
    const EulerParameters theta = ConstMap4(yi + k.theta);
    const EulerParameters v_theta = ConstMap4(yi + k.v_theta);
    const double lambda = yi[k.lambda];
    const double mu = yi[k.mu];

    if (k.p >= 0) {
      Map3(ri + k.p) = ConstMap3(ypi + k.p) - s.v_WBr;           // ṗ − v
      Map3(ri + k.v) = b.mass() * ConstMap3(ypi + k.v) - w.f_W;  // m v̇ − f
    }
    Map4(ri + k.theta) = ConstMap4(ypi + k.theta) - v_theta + 2.0 * mu * theta;  // GGL
    const Matrix34d g_bar = g_bar_matrix(theta);
    const Eigen::Vector3d alpha_B = 2.0 * g_bar * ConstMap4(ypi + k.v_theta);
    const Eigen::Vector3d tau_B = scratch.workspace.kinematics[i].R_WB.transpose() * w.tau_Br_W;
    const Eigen::Vector3d euler =
        b.I_Br_B() * alpha_B + s.w_WB_B.cross(b.I_Br_B() * s.w_WB_B) - tau_B;
    Map4(ri + k.v_theta) = 2.0 * g_bar.transpose() * euler + 2.0 * lambda * theta;
    ri[k.lambda] = theta.dot(v_theta);             // velocity constraint
    ri[k.mu] = 0.5 * (theta.squaredNorm() - 1.0);  // position constraint
  }
}

}  // namespace flexref::core
