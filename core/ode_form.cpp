#include "core/ode_form.hpp"

#include <cstddef>

namespace flexref::core {
namespace {

using ConstMap3 = Eigen::Map<const Eigen::Vector3d>;
using ConstMap4 = Eigen::Map<const Eigen::Vector4d>;
using Map3 = Eigen::Map<Eigen::Vector3d>;
using Map4 = Eigen::Map<Eigen::Vector4d>;

}  // namespace

OdeForm::OdeForm(const Model& model) : model_(&model), fixed_(model.initial_state()) {
  for (const Body& b : model.bodies()) {
    offsets_.push_back(size_);
    theta_offsets_.push_back(size_ + (b.is_free() ? 3 : 0));
    size_ += b.is_free() ? 13 : 7;
  }
}

OdeForm::Scratch OdeForm::make_scratch() const {
  Scratch s;
  s.state = fixed_;
  s.workspace = model_->make_workspace();
  s.accelerations.resize(fixed_.size());
  return s;
}

void OdeForm::pack(const State& state, double* y) const {
  for (std::size_t i = 0; i < state.size(); ++i) {
    double* yi = y + offsets_[i];
    const BodyState& s = state[i];
    if (model_->body(static_cast<int>(i)).is_free()) {
      Map3{yi} = s.p_WBr;
      Map4(yi + 3) = s.theta_WB;
      Map3(yi + 7) = s.v_WBr;
      Map3(yi + 10) = s.w_WB_B;
    } else {
      Map4{yi} = s.theta_WB;
      Map3(yi + 4) = s.w_WB_B;
    }
  }
}

void OdeForm::unpack(const double* y, State& state) const {
  for (std::size_t i = 0; i < state.size(); ++i) {
    const double* yi = y + offsets_[i];
    BodyState& s = state[i];
    if (model_->body(static_cast<int>(i)).is_free()) {
      s.p_WBr = ConstMap3(yi);
      s.theta_WB = ConstMap4(yi + 3).normalized();
      s.v_WBr = ConstMap3(yi + 7);
      s.w_WB_B = ConstMap3(yi + 10);
    } else {
      s.p_WBr = fixed_[i].p_WBr;
      s.theta_WB = ConstMap4(yi).normalized();
      s.v_WBr.setZero();
      s.w_WB_B = ConstMap3(yi + 4);
    }
  }
}

void OdeForm::rhs(const LoadContext& context, const double* y, double* ydot,
                  Scratch& scratch) const {
  unpack(y, scratch.state);
  model_->compute_accelerations(context, scratch.state, scratch.workspace, scratch.accelerations);
  for (std::size_t i = 0; i < scratch.state.size(); ++i) {
    double* fi = ydot + offsets_[i];
    const double* yi = y + offsets_[i];
    const BodyState& s = scratch.state[i];
    const BodyAcceleration& a = scratch.accelerations[i];
    if (model_->body(static_cast<int>(i)).is_free()) {
      Map3{fi} = s.v_WBr;                                                // ṗ = v
      Map4(fi + 3) = euler_parameter_rate(ConstMap4(yi + 3), s.w_WB_B);  // θ̇ = ½ θ ⊗ (0, ω̄)
      Map3(fi + 7) = a.a_WBr;                                            // v̇ = a
      Map3(fi + 10) = a.alpha_WB_B;                                      // ω̄̇ = α̅
    } else {
      Map4{fi} = euler_parameter_rate(ConstMap4(yi), s.w_WB_B);
      Map3(fi + 4) = a.alpha_WB_B;
    }
  }
}

void OdeForm::normalize_euler_parameters(double* y) const {
  for (int offset : theta_offsets_) {
    Map4 theta(y + offset);
    theta /= theta.norm();
  }
}

}  // namespace flexref::core
