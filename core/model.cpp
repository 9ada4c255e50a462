#include "core/model.hpp"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace flexref::core {

Model::Model(std::vector<Body> bodies, std::vector<std::unique_ptr<const ForceElement>> elements)
    : bodies_(std::move(bodies)), elements_(std::move(elements)) {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (bodies_[i].name() == bodies_[j].name()) {
        throw std::invalid_argument("duplicate body name '" + bodies_[i].name() + "'");
      }
    }
  }
  for (const auto& e : elements_) {
    if (e->max_body_index() >= static_cast<int>(bodies_.size())) {
      throw std::invalid_argument("a force element refers to body " +
                                  std::to_string(e->max_body_index()) + " of " +
                                  std::to_string(bodies_.size()));
    }
    e->append_discontinuities(discontinuities_);
    velocity_dependent_ = velocity_dependent_ || e->depends_on_velocity();
  }
  std::sort(discontinuities_.begin(), discontinuities_.end());
  discontinuities_.erase(std::unique(discontinuities_.begin(), discontinuities_.end()),
                         discontinuities_.end());
}

int Model::body_index(const std::string& name) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].name() == name) return static_cast<int>(i);
  }
  return -1;
}

State Model::initial_state() const {
  State state(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyInitialState& init = b.description().initial;
    BodyState& s = state[i];
    const Eigen::Matrix3d R_WB = rotation_matrix(init.theta_WB);
    s.theta_WB = init.theta_WB;
    s.w_WB_B = init.w_WB_B;
    // p_WBr = p_WBo + A p_BoBr;  v_WBr = v_WBo + A (ω̄ × p_BoBr).
    s.p_WBr = init.p_WBo + R_WB * b.p_BoBr_B();
    s.v_WBr = b.is_free() ? Eigen::Vector3d(init.v_WBo + R_WB * init.w_WB_B.cross(b.p_BoBr_B()))
                          : Eigen::Vector3d::Zero();
  }
  return state;
}

Workspace Model::make_workspace() const {
  Workspace ws;
  ws.kinematics.resize(bodies_.size());
  ws.wrenches.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    ws.kinematics[i].p_BoBr_B = bodies_[i].p_BoBr_B();
  }
  return ws;
}

void Model::compute_wrenches(const LoadContext& context, const State& state, Workspace& ws) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    ws.kinematics[i].state = &state[i];
    ws.kinematics[i].R_WB = rotation_matrix(state[i].theta_WB);
    ws.wrenches[i].set_zero();
  }
  for (const auto& e : elements_) e->add_wrenches(context, ws.kinematics, ws.wrenches);
}

void Model::accelerations_from_wrenches(const State& state, const Workspace& ws,
                                        Accelerations& accelerations) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Wrench& w = ws.wrenches[i];
    BodyAcceleration& a = accelerations[i];
    // Newton: m a = f (free bodies, Br = Bcm); a pivot does not translate.
    a.a_WBr = b.is_free() ? Eigen::Vector3d(w.f_W / b.mass()) : Eigen::Vector3d::Zero();
    // Euler about Br: I α̅ = Aᵀ τ − ω̄ × I ω̄   (paper eq. 25).
    const Eigen::Vector3d tau_B = ws.kinematics[i].R_WB.transpose() * w.tau_Br_W;
    a.alpha_WB_B = b.I_Br_B_inverse() * (tau_B - s.w_WB_B.cross(b.I_Br_B() * s.w_WB_B));
  }
}

void Model::compute_accelerations(const LoadContext& context, const State& state, Workspace& ws,
                                  Accelerations& accelerations) const {
  compute_wrenches(context, state, ws);
  accelerations_from_wrenches(state, ws, accelerations);
}

double Model::kinetic_energy(const State& state) const {
  double t = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    // T = ½ m |v_Bcm|² + ½ ω̄ᵀ I_Bcm ω̄ (free, Br = Bcm);  T = ½ ω̄ᵀ I_Pv ω̄ (pivot).
    t += 0.5 * s.w_WB_B.dot(b.I_Br_B() * s.w_WB_B);
    if (b.is_free()) t += 0.5 * b.mass() * s.v_WBr.squaredNorm();
  }
  return t;
}

double Model::potential_energy(const LoadContext& context, const State& state,
                               Workspace& ws) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    ws.kinematics[i].state = &state[i];
    ws.kinematics[i].R_WB = rotation_matrix(state[i].theta_WB);
  }
  double v = 0.0;
  for (const auto& e : elements_) v += e->potential_energy(context, ws.kinematics);
  return v;
}

Eigen::Vector3d Model::linear_momentum_W(const State& state) const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Eigen::Matrix3d R_WB = rotation_matrix(s.theta_WB);
    p += b.mass() * (s.v_WBr + R_WB * s.w_WB_B.cross(b.p_BrBcm_B()));
  }
  return p;
}

Eigen::Vector3d Model::angular_momentum_W(const State& state) const {
  // H_O = Σ p_WBr × m v_Bcm + A (I_Br ω̄ + m p_BrBcm × v_Br expressed in B); for a free body
  // (Br = Bcm) and a pivot body (v_Br = 0) the last term vanishes.
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Eigen::Matrix3d R_WB = rotation_matrix(s.theta_WB);
    const Eigen::Vector3d v_WBcm = s.v_WBr + R_WB * s.w_WB_B.cross(b.p_BrBcm_B());
    h += s.p_WBr.cross(b.mass() * v_WBcm) + R_WB * (b.I_Br_B() * s.w_WB_B);
  }
  return h;
}

Eigen::Vector3d Model::p_WBo(int i, const BodyState& s) const {
  return s.p_WBr - rotation_matrix(s.theta_WB) * body(i).p_BoBr_B();
}

Eigen::Vector3d Model::v_WBo(int i, const BodyState& s) const {
  return s.v_WBr - rotation_matrix(s.theta_WB) * s.w_WB_B.cross(body(i).p_BoBr_B());
}

Eigen::Vector3d Model::p_WP(int i, const BodyState& s, const Eigen::Vector3d& p_BoP_B) const {
  return s.p_WBr + rotation_matrix(s.theta_WB) * (p_BoP_B - body(i).p_BoBr_B());
}

}  // namespace flexref::core
