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
  layout_.offsets.push_back(0);
  for (const Body& b : bodies_) layout_.offsets.push_back(layout_.size() + 6 + b.mode_count());
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
  initial_state_ = scene_initial_state();
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
typename ModelTpl<S>::State ModelTpl<S>::initial_state() const {
  return initial_state_;
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
        prescribed_attitude_in<S>(d.prescribed.law, b.axis_W(), b.theta_WB0(), t);
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
    ws.constraint = ConstraintSolveTpl<S>(constraints_->row_count(), layout_, active_rows_);
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
    ws.kinematics[i].R_WB = rotation::rotation_matrix<S>(state[i].theta_WB);
    ws.kinematics[i].q_f = lte ? &ws.flexible[i].zero : &state[i].q_f;
  }
}

template <typename S>
void ModelTpl<S>::compute_wrenches(const LoadContext& context, const State& state,
                                   Workspace& ws) const {
  ws.time = context.t;
  pose_bodies(state, ws);
  for (WrenchTpl<S>& w : ws.wrenches) w.set_zero();
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    elements_[e]->add_wrenches(element_context(context, ws, e), ws.kinematics, ws.wrenches);
  }
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
typename ModelTpl<S>::Vector3 ModelTpl<S>::prescribed_alpha_WB_B(int i, const Workspace& ws) const {
  const Body& b = bodies_[static_cast<std::size_t>(i)];
  if (!b.is_prescribed()) return Vector3::Zero();
  if (ws.time == ws.prescribed_time) return ws.prescribed_alpha[static_cast<std::size_t>(i)];
  return prescribed_attitude_in<S>(b.description().prescribed.law, b.axis_W(), b.theta_WB0(),
                                   ws.time)
      .alpha_WB_B;
}

template <typename S>
void ModelTpl<S>::flexible_accelerations(int i, const BodyState& s, Workspace& ws,
                                         BodyAcceleration& a) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  solve_flexible_accelerations_tpl<S>(b.modal_mass(), formulation_, fs.terms, b.motion(),
                                      prescribed_alpha_WB_B(i, ws), fs.rhs, fs.solve, fs.x);
  a.a_WBr = fs.x.template head<3>();
  a.alpha_WB_B = fs.x.template segment<3>(3);
  a.qdd_f = fs.x.tail(n);
}

template <typename S>
void ModelTpl<S>::accelerations_from_wrenches(const State& state, Workspace& ws,
                                              Accelerations& accelerations) const {
  free_accelerations(state, ws, accelerations);
  if (constraints_) apply_constraints(ws.time, ws, accelerations);
}

template <typename S>
void ModelTpl<S>::free_accelerations(const State& state, Workspace& ws,
                                     Accelerations& accelerations) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (b.is_flexible()) {
      flexible_accelerations(static_cast<int>(i), state[i], ws, accelerations[i]);
      continue;
    }
    BodyAcceleration& a = accelerations[i];
    rigid_body_accelerations_tpl<S>(
        b.motion(), b.mass(), b.I_Br_B(), b.I_Br_B_inverse(), ws.kinematics[i].R_WB, ws.wrenches[i],
        state[i].w_WB_B, prescribed_alpha_WB_B(static_cast<int>(i), ws), a.a_WBr, a.alpha_WB_B);
  }
}

template <typename S>
void ModelTpl<S>::compute_accelerations(const LoadContext& context, const State& state,
                                        Workspace& ws, Accelerations& accelerations) const {
  compute_wrenches(context, state, ws);
  accelerations_from_wrenches(state, ws, accelerations);
}

template <typename S>
void ModelTpl<S>::dynamics_residual(int i, const BodyState& s, const BodyAcceleration& acc,
                                    Workspace& ws, Eigen::Ref<Vector> out) const {
  const auto k = static_cast<std::size_t>(i);
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
void ModelTpl<S>::modal_accelerations(int i, const BodyState& s, const Vector3& a_WBr,
                                      const Vector3& alpha_WB_B, Workspace& ws,
                                      Vector& qdd_f) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  if (b.is_prescribed()) {
    fs.x.template head<3>().setZero();
    fs.x.template segment<3>(3) = prescribed_alpha_WB_B(i, ws);
  } else {
    fs.x.template head<3>() = a_WBr;
    fs.x.template segment<3>(3) = alpha_WB_B;
  }
  flexible::solve_modal_rows_tpl<S>(b.modal_mass(), fs.terms, fs.rhs, fs.solve, fs.x);
  qdd_f = fs.x.tail(n);
}

template <typename S>
S ModelTpl<S>::driving_torque(int i, const BodyState& s, const BodyAcceleration& acc,
                              Workspace& ws) const {
  const Body& b = body(i);
  if (!b.is_prescribed()) return S(0);
  FlexibleScratch& fs = ws.flexible[static_cast<std::size_t>(i)];
  dynamics_residual(i, s, acc, ws, fs.residual);
  // The drive's torque τ_d enters the rotation rows as +Aᵀ τ_d, so τ_d,B = the residual there.
  const Vector3 tau_drive_W =
      ws.kinematics[static_cast<std::size_t>(i)].R_WB * fs.residual.template segment<3>(3);
  return b.axis_W().dot(tau_drive_W);
}

template <typename S>
S ModelTpl<S>::kinetic_energy(const State& state) const {
  S t = S(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    if (b.is_flexible()) {
      const Eigen::Matrix<S, 3, 3> R_WB = rotation::rotation_matrix<S>(s.theta_WB);
      if constexpr (std::is_same_v<S, double>) {
        t += flexible::flexible_kinetic_energy(b.invariants(), R_WB, s.q_f, s.v_WBr, s.w_WB_B,
                                               s.qd_f);
      } else {
        // ½ vᵀ M v from the mass matrix's blocks at the state's q_f (under LTE too), v = (v_WBr,
        // ω̄, q̇_f): ½ [v_rᵀ M_rr v_r + 2 v_rᵀ M_rf q̇ + q̇ᵀ m_ff q̇]. Double's route
        // (flexible_kinetic_energy) sums the invariants' products without scratch; in S the
        // blocks' scratch is formed here (an output, not an evaluation of the integrators).
        flexible::InertiaTermsTpl<S> terms = flexible::make_inertia_terms_tpl<S>(b.mode_count());
        const Vector zero = Vector::Zero(b.mode_count());
        flexible::compute_modal_products_tpl<S>(b.invariants(), s.q_f, zero, terms);
        flexible::assemble_inertia_terms_tpl<S>(b.invariants(), R_WB, s.q_f, s.w_WB_B, zero, terms);
        Eigen::Matrix<S, 6, 1> v_r;
        v_r << s.v_WBr, s.w_WB_B;
        t += S(0.5) * (v_r.dot(terms.M_rr * v_r) + S(2) * v_r.dot(terms.M_rf * s.qd_f) +
                       s.qd_f.dot(b.invariants().m_ff * s.qd_f));
      }
      continue;
    }
    // T = ½ m |v_Bcm|² + ½ ω̄ᵀ I_Bcm ω̄ (free, Br = Bcm);  T = ½ ω̄ᵀ I_Pv ω̄ (pivot).
    t += S(0.5) * s.w_WB_B.dot(b.I_Br_B() * s.w_WB_B);
    if (b.is_free()) t += S(0.5) * b.mass() * s.v_WBr.squaredNorm();
  }
  return t;
}

template <typename S>
S ModelTpl<S>::potential_energy(const LoadContext& context, const State& state,
                                Workspace& ws) const {
  pose_bodies(state, ws);
  S v = elastic_energy(state);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    v += elements_[e]->potential_energy(element_context(context, ws, e), ws.kinematics);
  }
  return v;
}

template <typename S>
template <typename Evaluate>
void ModelTpl<S>::for_each_switching_element(std::span<S> out, Evaluate&& evaluate) const {
  std::size_t offset = 0;
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const auto count = static_cast<std::size_t>(elements_[e]->switching_function_count());
    if (count == 0) continue;
    evaluate(*elements_[e], e, out.subspan(offset, count));
    offset += count;
  }
}

template <typename S>
void ModelTpl<S>::switching_functions(const LoadContext& context, const State& state, Workspace& ws,
                                      std::span<S> g) const {
  pose_bodies(state, ws);
  for_each_switching_element(g, [&](const ForceElement& e, std::size_t j, std::span<S> values) {
    e.switching_functions(element_context(context, ws, j), ws.kinematics, values);
  });
}

template <typename S>
void ModelTpl<S>::clamp_functions(const LoadContext& context, const State& state, Workspace& ws,
                                  std::span<S> c) const {
  pose_bodies(state, ws);
  for_each_switching_element(c, [&](const ForceElement& e, std::size_t j, std::span<S> values) {
    e.clamp_functions(element_context(context, ws, j), ws.kinematics, values);
  });
}

template <typename S>
void ModelTpl<S>::compute_wrenches_and_rates(const LoadContext& context, const State& state,
                                             Workspace& ws, std::span<S> rates, std::span<S> g,
                                             std::span<S> c) const {
  ws.time = context.t;
  pose_bodies(state, ws);
  for (WrenchTpl<S>& w : ws.wrenches) w.set_zero();
  const bool with_rates = tracks_work() && !rates.empty();
  // Ẇ_d = Σ q̇_fᵀ D q̇_f + the elements' dissipation (dissipated_power's sum, in its order).
  S dissipation = with_rates ? modal_dissipated_power(state) : S(0);
  std::size_t offset = 0;
  for (std::size_t j = 0; j < elements_.size(); ++j) {
    const ForceElementTpl<S>& e = *elements_[j];
    const auto count = static_cast<std::size_t>(e.switching_function_count());
    const int channel = element_channels_[j];
    std::span<WearSampleTpl<S>> wear;
    if (with_rates && channel >= 0) wear = {&ws.wear[static_cast<std::size_t>(channel)], 1};
    e.add_wrenches_and_rates(element_context(context, ws, j), ws.kinematics, ws.wrenches,
                             with_rates ? &dissipation : nullptr, wear,
                             g.empty() ? g : g.subspan(offset, count),
                             c.empty() ? c : c.subspan(offset, count));
    offset += count;
  }
  if (!with_rates) return;
  // Then Ẇ_a = the applied power and each wear channel's |F_t·v_t| (integral_rates' layout).
  const IntegralLayout& k = integral_layout_;
  rates[0] = dissipation;
  if (k.applied >= 0) rates[static_cast<std::size_t>(k.applied)] = applied_power(context, ws);
  if (k.drive >= 0) rates[static_cast<std::size_t>(k.drive)] = S(0);
  for (std::size_t ch = 0; ch < ws.wear.size(); ++ch) {
    rates[static_cast<std::size_t>(k.first_wear) + ch] = ws.wear[ch].wear_power;
  }
}

template <typename S>
S ModelTpl<S>::dissipated_power(const LoadContext& context, const State& state,
                                Workspace& ws) const {
  pose_bodies(state, ws);
  S p = modal_dissipated_power(state);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    p += elements_[e]->dissipated_power(element_context(context, ws, e), ws.kinematics);
  }
  return p;
}

template <typename S>
S ModelTpl<S>::modal_dissipated_power(const State& state) const {
  S p = S(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].is_flexible()) {
      // q̇_fᵀ D q̇_f with D = diag(d_i)
      p += state[i].qd_f.dot(bodies_[i].modal_damping().cwiseProduct(state[i].qd_f));
    }
  }
  return p;
}

template <typename S>
S ModelTpl<S>::applied_power(const LoadContext& context, const Workspace& ws) const {
  S p = S(0);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    p += elements_[e]->applied_power(element_context(context, ws, e), ws.kinematics);
  }
  return p;
}

template <typename S>
S ModelTpl<S>::elastic_energy(const State& state) const {
  S v = S(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (!bodies_[i].is_flexible()) continue;
    // ½ q_fᵀ K q_f with K = diag(K_i)
    v += S(0.5) * state[i].q_f.dot(bodies_[i].modal_stiffness().cwiseProduct(state[i].q_f));
  }
  return v;
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::linear_momentum_W(
    const State& state) const requires std::is_same_v<S, double> {
  Vector3 p = Vector3::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Eigen::Matrix<S, 3, 3> R_WB = rotation::rotation_matrix<S>(s.theta_WB);
    if (b.is_flexible()) {
      // First row of M v: m Ṙ + A (ω̄ × s_t + S q̇_f)
      const flexible::ModalInvariantsTpl<S>& inv = b.invariants();
      p += inv.mass * s.v_WBr + R_WB * (s.w_WB_B.cross(flexible::first_moment(inv, s.q_f)) +
                                        flexible::first_moment_rate(inv, s.q_f, s.qd_f));
      continue;
    }
    p += b.mass() * (s.v_WBr + R_WB * s.w_WB_B.cross(b.p_BrBcm_B()));
  }
  return p;
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::angular_momentum_W(
    const State& state) const requires std::is_same_v<S, double> {
  // H_O = Σ p_WBr × m v_Bcm + A (I_Br ω̄ + m p_BrBcm × v_Br expressed in B); for a free body
  // (Br = Bcm) and a pivot body (v_Br = 0) the last term vanishes.
  Vector3 h = Vector3::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Eigen::Matrix<S, 3, 3> R_WB = rotation::rotation_matrix<S>(s.theta_WB);
    if (b.is_flexible()) {
      // H_O = p_WBr × p + H_Br,  H_Br = A (s̃_t Aᵀ Ṙ + Ī_θθ ω̄ + Ī_θf q̇_f)  (θ row of M v)
      const flexible::ModalInvariantsTpl<S>& inv = b.invariants();
      const Vector3 s_t = flexible::first_moment(inv, s.q_f);
      const Vector3 p_W =
          inv.mass * s.v_WBr +
          R_WB * (s.w_WB_B.cross(s_t) + flexible::first_moment_rate(inv, s.q_f, s.qd_f));
      const Vector3 h_B = s_t.cross(R_WB.transpose() * s.v_WBr) +
                          flexible::inertia_theta_theta(inv, s.q_f) * s.w_WB_B +
                          flexible::inertia_theta_f(inv, s.q_f) * s.qd_f;
      h += s.p_WBr.cross(p_W) + R_WB * h_B;
      continue;
    }
    const Vector3 v_WBcm = s.v_WBr + R_WB * s.w_WB_B.cross(b.p_BrBcm_B());
    h += s.p_WBr.cross(b.mass() * v_WBcm) + R_WB * (b.I_Br_B() * s.w_WB_B);
  }
  return h;
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::p_WBo(int i, const BodyState& s) const {
  return s.p_WBr - rotation::rotation_matrix<S>(s.theta_WB) * body(i).p_BoBr_B();
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::v_WBo(int i, const BodyState& s) const {
  return s.v_WBr - rotation::rotation_matrix<S>(s.theta_WB) * s.w_WB_B.cross(body(i).p_BoBr_B());
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::p_WP(int i, const BodyState& s,
                                                const Eigen::Vector3d& p_BoP_B) const {
  return s.p_WBr + rotation::rotation_matrix<S>(s.theta_WB) * body(i).p_BrP_B(p_BoP_B);
}

template <typename S>
typename ModelTpl<S>::Vector3 ModelTpl<S>::p_WP(int i, const BodyState& s,
                                                const TrackedPoint& point) const {
  return s.p_WBr + rotation::rotation_matrix<S>(s.theta_WB) * body(i).p_BrP_B(point, s.q_f);
}

// --- Wear channels and tracked integrals (docs/output.md): W_d, the applied work W_a of loads
// that keep doing work, and each contact's wear work ∫ |F_t·v_t| dt. -----------------------

template <typename S>
void ModelTpl<S>::wear_samples(const LoadContext& context, const State& state,
                               Workspace& ws) const {
  pose_bodies(state, ws);
  for (std::size_t c = 0; c < wear_elements_.size(); ++c) {
    const auto e = static_cast<std::size_t>(wear_elements_[c]);
    elements_[e]->wear_samples(element_context(context, ws, e), ws.kinematics,
                               std::span<WearSampleTpl<S>>(&ws.wear[c], 1));
  }
}

template <typename S>
void ModelTpl<S>::wear_depth_rates(const LoadContext& context, const State& state, Workspace& ws,
                                   std::span<S> rates) const {
  if (wear_depth_count_ == 0) return;
  pose_bodies(state, ws);
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const auto count = static_cast<std::size_t>(elements_[e]->wear_depth_count());
    if (count == 0) continue;
    elements_[e]->wear_depth_rates(element_context(context, ws, e), ws.kinematics,
                                   rates.subspan(element_depth_first_[e], count));
  }
}

template <typename S>
S ModelTpl<S>::wear_depth_max(int channel, const State& state) const {
  const int count = channel_depth_count(channel);
  if (count == 0) return S(0);
  return state.wear_depth.segment(channel_depth_first(channel), count).maxCoeff();
}

template <typename S>
S ModelTpl<S>::wear_volume(int channel, const State& state) const {
  const int first = channel_depth_first(channel);
  S v = S(0);
  for (int k = first; k < first + channel_depth_count(channel); ++k) {
    v += S(wear_depth_areas_[static_cast<std::size_t>(k)]) * state.wear_depth(k);
  }
  return v;
}

template <typename S>
void ModelTpl<S>::integral_rates(const LoadContext& context, const State& state, Workspace& ws,
                                 std::span<S> rates, const Vector* constraint_force) const {
  const IntegralLayout& k = integral_layout_;
  if (k.drive >= 0) {
    // The joints' power first (a constrained solve of its own when the caller has none: it
    // overwrites the loads in ws, which the rates below evaluate again).
    if (constraint_force == nullptr) {
      compute_wrenches(context, state, ws);
      free_accelerations(state, ws, ws.integral_accelerations);
      apply_constraints(context.t, ws, ws.integral_accelerations);
      constraint_force = &ws.constraint.force;
    }
    rates[static_cast<std::size_t>(k.drive)] = constraint_power(state, *constraint_force, ws);
  }
  rates[0] = dissipated_power(context, state, ws);  // poses the bodies
  if (k.count == 0) return;
  if (k.applied >= 0) rates[static_cast<std::size_t>(k.applied)] = applied_power(context, ws);
  for (std::size_t c = 0; c < wear_elements_.size(); ++c) {
    const auto e = static_cast<std::size_t>(wear_elements_[c]);
    elements_[e]->wear_samples(element_context(context, ws, e), ws.kinematics,
                               std::span<WearSampleTpl<S>>(&ws.wear[c], 1));
    rates[static_cast<std::size_t>(k.first_wear) + c] = ws.wear[c].wear_power;
  }
}

template <typename S>
S ModelTpl<S>::constraint_power(const State& state, const Vector& constraint_force,
                                Workspace& ws) const {
  stack_velocities(state, ws.constraint.v);
  return ws.constraint.v.dot(constraint_force);
}

}  // namespace flexref::core

#include "core/model_joints_impl.hpp"
