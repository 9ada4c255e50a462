#pragma once
/// \file model_impl.hpp
/// ModelTpl<S>'s definitions, included by the translation units that instantiate it
/// (core/model.cpp for double; precision/model_instances_*.cpp for long double and float128).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "core/body_equations_tpl.hpp"
#include "core/model.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "flexible/inertia_terms_tpl.hpp"
#include "flexible/mass_matrix_solve_tpl.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::core {

template <typename S>
ModelTpl<S>::ModelTpl(std::vector<Body> bodies,
                      std::vector<std::unique_ptr<const ForceElement>> elements,
                      FlexibleFormulation formulation,
                      std::unique_ptr<const ConstraintEquations> constraints,
                      ConstraintOptions options)
    : bodies_(std::move(bodies)),
      elements_(std::move(elements)),
      formulation_(formulation),
      constraints_(std::move(constraints)) {
  for (const Body& b : bodies_) flexible_ = flexible_ || b.is_flexible();
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
    switching_count_ += e->switching_function_count();
  }
  dissipates_ = velocity_dependent_;
  for (const Body& b : bodies_) {
    dissipates_ =
        dissipates_ || (b.is_flexible() && b.modal_damping().cwiseAbs().maxCoeff() > S(0));
  }
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const ForceElementTpl<S>& element = *elements_[e];
    const int channel =
        element.wear_channel_count() > 0 ? static_cast<int>(wear_names_.size()) : -1;
    if (channel >= 0) {
      wear_names_.push_back(element.wear_channel_name());
      wear_elements_.push_back(static_cast<int>(e));
    }
    element_channels_.push_back(channel);
    element_depth_first_.push_back(static_cast<std::size_t>(wear_depth_count_));
    if (element.wear_depth_count() > 0 && channel < 0) {
      throw std::invalid_argument("a wear law needs a named contact");
    }
    for (int k = 0; k < element.wear_depth_count(); ++k) {
      wear_depth_areas_.push_back(element.wear_depth_area(k));
    }
    wear_depth_count_ += element.wear_depth_count();
    switching_channels_.insert(switching_channels_.end(),
                               static_cast<std::size_t>(element.switching_function_count()),
                               channel);
    applied_work_ = applied_work_ || element.tracks_applied_work();
  }
  for (std::size_t i = 0; i < wear_names_.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (wear_names_[i] == wear_names_[j]) {
        throw std::invalid_argument("duplicate contact name '" + wear_names_[i] + "'");
      }
    }
  }
  layout_ = VelocityLayout::of(bodies_);
  if (constraints_) {
    constraints_->append_discontinuities(discontinuities_);
    for (int j = 0; j < constraints_->joint_count(); ++j) {
      drive_work_ = drive_work_ || constraints_->driven(j);
    }
  }
  if (tracks_work()) {
    IntegralLayout& k = integral_layout_;
    k.count = 1;
    if (applied_work_) k.applied = k.count++;
    if (drive_work_) k.drive = k.count++;
    if (!wear_names_.empty()) {
      k.first_wear = k.count;
      k.count += static_cast<int>(wear_names_.size());
    }
  }
  std::sort(discontinuities_.begin(), discontinuities_.end());
  discontinuities_.erase(std::unique(discontinuities_.begin(), discontinuities_.end()),
                         discontinuities_.end());
  if (constraints_) assemble_initial_state(options);
}

template <typename S>
typename ModelTpl<S>::State ModelTpl<S>::scene_initial_state() const {
  State state(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyInitialState& init = b.description().initial;
    BodyState& s = state[i];
    const Eigen::Matrix<S, 3, 3> R_WB = rotation::rotation_matrix<S>(b.theta_WB0());
    const Vector3 w_WB_B = init.w_WB_B.template cast<S>();
    s.theta_WB = b.theta_WB0();
    s.w_WB_B = w_WB_B;
    // p_WBr = p_WBo + A p_BoBr;  v_WBr = v_WBo + A (ω̄ × p_BoBr).
    s.p_WBr = init.p_WBo.template cast<S>() + R_WB * b.p_BoBr_B();
    s.v_WBr = b.is_free()
                  ? Vector3(init.v_WBo.template cast<S>() + R_WB * w_WB_B.cross(b.p_BoBr_B()))
                  : Vector3::Zero();
    const Eigen::Index n = b.mode_count();
    s.q_f = Vector::Zero(n);
    s.qd_f = Vector::Zero(n);
    if (b.is_flexible()) {
      const FlexiblePart& f = *b.description().flexible;
      if (f.q0.size() == n) s.q_f = f.q0.template cast<S>();
      if (f.qd0.size() == n) s.qd_f = f.qd0.template cast<S>();
    }
  }
  apply_prescribed_motion(S(0), state);
  // The contacts' worn depths start at their laws' initial depths (zero unless given).
  state.wear_depth = Vector::Zero(wear_depth_count_);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const WearLaw* law = elements_[e]->wear_law();
    if (law == nullptr) continue;
    for (std::size_t k = 0; k < law->initial_depth.size(); ++k) {
      state.wear_depth(static_cast<Eigen::Index>(element_depth_first_[e] + k)) =
          S(law->initial_depth[k]);
    }
  }
  return state;
}

template <typename S>
int ModelTpl<S>::body_index(const std::string& name) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].name() == name) return static_cast<int>(i);
  }
  return -1;
}

template <typename S>
typename ModelTpl<S>::Accelerations ModelTpl<S>::make_accelerations() const {
  Accelerations acc(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    acc[i].qdd_f = Vector::Zero(bodies_[i].mode_count());
  }
  return acc;
}

template <typename S>
void ModelTpl<S>::apply_prescribed_motion(S t, State& state) const {
  set_prescribed_motion(t, state, nullptr);
}

template <typename S>
void ModelTpl<S>::apply_prescribed_motion(S t, State& state, Workspace& ws) const {
  set_prescribed_motion(t, state, &ws.prescribed_alpha);
  ws.prescribed_time = t;
}

template <typename S>
void ModelTpl<S>::set_prescribed_motion(S t, State& state, std::vector<Vector3>* alpha) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (!b.is_prescribed()) continue;
    const RigidBodyDescription& d = b.description();
    const PrescribedAttitudeTpl<S> law =
        prescribed_attitude<S>(d.prescribed.law, b.axis_W(), b.theta_WB0(), t);
    BodyState& s = state[i];
    s.p_WBr = d.initial.p_WBo.template cast<S>();  // Br = Bo, fixed on the axis
    s.v_WBr.setZero();
    s.theta_WB = law.theta_WB;
    s.w_WB_B = law.w_WB_B;
    if (alpha != nullptr) (*alpha)[i] = law.alpha_WB_B;
  }
}

template <typename S>
typename ModelTpl<S>::Workspace ModelTpl<S>::make_workspace() const {
  Workspace ws;
  ws.prescribed_alpha.assign(bodies_.size(), Vector3::Zero());
  ws.kinematics.resize(bodies_.size());
  ws.wrenches.resize(bodies_.size());
  ws.flexible.resize(bodies_.size());
  ws.wear.resize(wear_names_.size());
  if (drive_work_) ws.integral_accelerations = make_accelerations();
  if (constraints_) {
    ws.constraint = ConstraintSolveTpl<S>(*constraints_, layout_, active_rows_);
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    ws.kinematics[i].p_BoBr_B = b.p_BoBr_B();
    const Eigen::Index n = b.mode_count();
    ws.wrenches[i].Q_f = Vector::Zero(n);
    // The rows driving_torque evaluates (rigid prescribed bodies too).
    ws.flexible[i].residual = Vector::Zero(6 + n);
    if (!b.is_flexible()) continue;
    ws.kinematics[i].invariants = &b.invariants();
    FlexibleScratch& fs = ws.flexible[i];
    fs.terms = flexible::make_inertia_terms_tpl<S>(static_cast<int>(n));
    fs.solve = flexible::make_mass_solve_scratch_tpl<S>(static_cast<int>(n));
    fs.rhs = Vector::Zero(6 + n);
    fs.x = Vector::Zero(6 + n);
    fs.zero = Vector::Zero(n);
  }
  return ws;
}

template <typename S>
void ModelTpl<S>::pose_bodies(const State& state, Workspace& ws) const {
  pose_bodies(state, nullptr, ws);
}

template <typename S>
void ModelTpl<S>::pose_bodies(const State& state, const Eigen::Matrix<S, 3, 3>* R_WB,
                              Workspace& ws) const {
  // Loads see the state's q_f under the coupled model, q_f = 0 under LTE (undeformed body).
  const bool lte = formulation_ == FlexibleFormulation::kLte;
  if (state.wear_depth.size() != wear_depth_count_) {
    throw std::invalid_argument("the state has " + std::to_string(state.wear_depth.size()) +
                                " worn depths; the model integrates " +
                                std::to_string(wear_depth_count_));
  }
  ws.wear_depth = std::span<const S>(state.wear_depth.data(),
                                     static_cast<std::size_t>(state.wear_depth.size()));
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    ws.kinematics[i].state = &state[i];
    ws.kinematics[i].R_WB =
        R_WB != nullptr ? R_WB[i] : rotation::rotation_matrix<S>(state[i].theta_WB);
    ws.kinematics[i].q_f = lte ? &ws.flexible[i].zero : &state[i].q_f;
  }
}

template <typename S>
typename ModelTpl<S>::Loads ModelTpl<S>::compute_wrenches(const LoadContext& context,
                                                          const State& state, Workspace& ws) const {
  pose_bodies(state, ws);
  return posed_wrenches(context, state, ws);
}

template <typename S>
typename ModelTpl<S>::Loads ModelTpl<S>::compute_wrenches(
    const LoadContext& context, const State& state, std::span<const Eigen::Matrix<S, 3, 3>> R_WB,
    Workspace& ws) const {
  if (R_WB.size() != bodies_.size()) {
    throw std::invalid_argument("compute_wrenches: " + std::to_string(R_WB.size()) +
                                " attitude matrices for " + std::to_string(bodies_.size()) +
                                " bodies");
  }
  pose_bodies(state, R_WB.data(), ws);
  return posed_wrenches(context, state, ws);
}

template <typename S>
typename ModelTpl<S>::Loads ModelTpl<S>::posed_wrenches(const LoadContext& context,
                                                        const State& state, Workspace& ws) const {
  for (WrenchTpl<S>& w : ws.wrenches) w.set_zero();
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    elements_[e]->add_wrenches(element_context(context, ws, e), ws.kinematics, ws.wrenches);
  }
  return Loads(context, state);
}

template <typename S>
void ModelTpl<S>::flexible_system(int i, const BodyState& s, Workspace& ws) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system_tpl<S>(b.invariants(), formulation_, ws.kinematics[k].R_WB, s, fs.zero,
                         ws.wrenches[k], b.modal_stiffness(), b.modal_damping(), fs.terms, fs.rhs);
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::prescribed_alpha_WB_B(int i, S t) const {
  const Body& b = bodies_[static_cast<std::size_t>(i)];
  if (!b.is_prescribed()) return Vector3::Zero();
  return prescribed_attitude<S>(b.description().prescribed.law, b.axis_W(), b.theta_WB0(), t)
      .alpha_WB_B;
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::prescribed_alpha_WB_B(int i, S t,
                                                                 const Workspace& ws) const {
  if (bodies_[static_cast<std::size_t>(i)].is_prescribed() && t == ws.prescribed_time) {
    return ws.prescribed_alpha[static_cast<std::size_t>(i)];
  }
  return prescribed_alpha_WB_B(i, t);
}

template <typename S>
void ModelTpl<S>::flexible_accelerations(int i, S t, const BodyState& s, Workspace& ws,
                                         BodyAcceleration& a) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  solve_flexible_accelerations_tpl<S>(b.modal_mass(), formulation_, fs.terms, b.motion(),
                                      prescribed_alpha_WB_B(i, t, ws), fs.rhs, fs.solve, fs.x);
  a.a_WBr = fs.x.template head<3>();
  a.alpha_WB_B = fs.x.template segment<3>(3);
  a.qdd_f = fs.x.tail(n);
}

template <typename S>
void ModelTpl<S>::accelerations_from_wrenches(const Loads& loads, const ConstraintTracker& tracker,
                                              Workspace& ws, Accelerations& accelerations,
                                              S stabilization) const {
  free_accelerations(loads, ws, accelerations);
  if (constraints_) {
    apply_constraints(loads.context().t, loads.state(), tracker, stabilization, ws, accelerations);
  }
}

template <typename S>
void ModelTpl<S>::free_accelerations(const Loads& loads, Workspace& ws,
                                     Accelerations& accelerations) const {
  const State& state = loads.state();
  const S t = loads.context().t;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (b.is_flexible()) {
      flexible_accelerations(static_cast<int>(i), t, state[i], ws, accelerations[i]);
      continue;
    }
    BodyAcceleration& a = accelerations[i];
    rigid_body_accelerations_tpl<S>(
        b.motion(), b.mass(), b.I_Br_B(), b.I_Br_B_inverse(), ws.kinematics[i].R_WB, ws.wrenches[i],
        state[i].w_WB_B, prescribed_alpha_WB_B(static_cast<int>(i), t, ws), a.a_WBr, a.alpha_WB_B);
  }
}

template <typename S>
typename ModelTpl<S>::Loads ModelTpl<S>::compute_accelerations(
    const LoadContext& context, const State& state, const ConstraintTracker& tracker, Workspace& ws,
    Accelerations& accelerations, S stabilization) const {
  const Loads loads = compute_wrenches(context, state, ws);
  accelerations_from_wrenches(loads, tracker, ws, accelerations, stabilization);
  return loads;
}

template <typename S>
void ModelTpl<S>::dynamics_residual(int i, const Loads& loads, const BodyAcceleration& acc,
                                    Workspace& ws, Eigen::Ref<Vector> out) const {
  const auto k = static_cast<std::size_t>(i);
  const BodyState& s = loads.state()[k];
  const Body& b = bodies_[k];
  const WrenchTpl<S>& w = ws.wrenches[k];
  const Eigen::Matrix<S, 3, 3>& R_WB = ws.kinematics[k].R_WB;
  if (!b.is_flexible()) {
    // m a − f;  I α̅ + ω̄ × I ω̄ − Aᵀ τ   (about Br)
    out.template head<3>() = b.mass() * acc.a_WBr - w.f_W;
    out.template segment<3>(3) = b.I_Br_B() * acc.alpha_WB_B +
                                 s.w_WB_B.cross(b.I_Br_B() * s.w_WB_B) -
                                 R_WB.transpose() * w.tau_Br_W;
    return;
  }
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  const flexible::InertiaTermsTpl<S>& t = fs.terms;
  // M x − rhs by blocks: [M_rr x_r + M_rf x_f; M_rfᵀ x_r + m_ff x_f] (LTE: no M_rf x_f in the
  // rigid rows).
  fs.x.template head<3>() = acc.a_WBr;
  fs.x.template segment<3>(3) = acc.alpha_WB_B;
  fs.x.tail(n) = acc.qdd_f;
  out = -fs.rhs;
  out.template head<6>().noalias() += t.M_rr * fs.x.template head<6>();
  if (n == 0) return;
  if (formulation_ == FlexibleFormulation::kCoupled) {
    out.template head<6>().noalias() += t.M_rf * fs.x.tail(n);
  }
  out.tail(n).noalias() += t.M_rf.transpose() * fs.x.template head<6>();
  out.tail(n).noalias() += b.invariants().m_ff * fs.x.tail(n);
}

template <typename S>
void ModelTpl<S>::residual_mass_matrix(int i, const Workspace& ws, Eigen::Ref<Matrix> out) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  const flexible::InertiaTermsTpl<S>& t = ws.flexible[k].terms;
  const Eigen::Index n = b.mode_count();
  out.template topLeftCorner<6, 6>() = t.M_rr;
  if (n == 0) return;
  if (formulation_ == FlexibleFormulation::kCoupled) {
    out.topRightCorner(6, n) = t.M_rf;
  } else {
    out.topRightCorner(6, n).setZero();
  }
  out.bottomLeftCorner(n, 6) = t.M_rf.transpose();
  out.bottomRightCorner(n, n) = b.invariants().m_ff;
}

template <typename S>
void ModelTpl<S>::modal_accelerations(int i, const Loads& loads, const Vector3& a_WBr,
                                      const Vector3& alpha_WB_B, Workspace& ws,
                                      Vector& qdd_f) const {
  const auto k = static_cast<std::size_t>(i);
  const BodyState& s = loads.state()[k];
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  if (b.is_prescribed()) {
    fs.x.template head<3>().setZero();
    fs.x.template segment<3>(3) = prescribed_alpha_WB_B(i, loads.context().t, ws);
  } else {
    fs.x.template head<3>() = a_WBr;
    fs.x.template segment<3>(3) = alpha_WB_B;
  }
  flexible::solve_modal_rows_tpl<S>(b.modal_mass(), fs.terms, fs.rhs, fs.solve, fs.x);
  qdd_f = fs.x.tail(n);
}

template <typename S>
S ModelTpl<S>::driving_torque(int i, const Loads& loads, const BodyAcceleration& acc,
                              Workspace& ws) const {
  const Body& b = body(i);
  if (!b.is_prescribed()) return S(0);
  FlexibleScratch& fs = ws.flexible[static_cast<std::size_t>(i)];
  dynamics_residual(i, loads, acc, ws, fs.residual);
  // The drive's torque τ_d enters the rotation rows as +Aᵀ τ_d, so τ_d,B = the residual there.
  const Vector3 tau_drive_W =
      ws.kinematics[static_cast<std::size_t>(i)].R_WB * fs.residual.template segment<3>(3);
  return b.axis_W().dot(tau_drive_W);
}

}  // namespace flexref::core

#include "core/model_energy_impl.hpp"
#include "core/model_initial_state_impl.hpp"
#include "core/model_integrals_impl.hpp"
#include "core/model_joints_impl.hpp"
#include "core/model_projection_impl.hpp"
