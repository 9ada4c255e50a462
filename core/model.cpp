#include "core/model.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/body_equations_tpl.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "flexible/mass_matrix_solve_tpl.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::core {

const char* to_string(FlexibleFormulation formulation) {
  return formulation == FlexibleFormulation::kLte ? "lte" : "coupled";
}

Model::Model(std::vector<Body> bodies, std::vector<std::unique_ptr<const ForceElement>> elements,
             FlexibleFormulation formulation,
             std::unique_ptr<const ConstraintEquations> constraints, ConstraintOptions options)
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
    dissipates_ = dissipates_ || (b.is_flexible() && b.modal_damping().cwiseAbs().maxCoeff() > 0.0);
  }
  for (std::size_t e = 0; e < elements_.size(); ++e) {
    const ForceElement& element = *elements_[e];
    const int channel =
        element.wear_channel_count() > 0 ? static_cast<int>(wear_names_.size()) : -1;
    if (channel >= 0) {
      wear_names_.push_back(element.wear_channel_name());
      wear_elements_.push_back(static_cast<int>(e));
    }
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
  if (constraints_) constraints_->append_discontinuities(discontinuities_);
  std::sort(discontinuities_.begin(), discontinuities_.end());
  discontinuities_.erase(std::unique(discontinuities_.begin(), discontinuities_.end()),
                         discontinuities_.end());
  initial_state_ = scene_initial_state();
  if (constraints_) assemble_initial_state(options);
}

State Model::scene_initial_state() const {
  State state(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyInitialState& init = b.description().initial;
    BodyState& s = state[i];
    const Eigen::Matrix3d R_WB = rotation::rotation_matrix(init.theta_WB);
    s.theta_WB = init.theta_WB;
    s.w_WB_B = init.w_WB_B;
    // p_WBr = p_WBo + A p_BoBr;  v_WBr = v_WBo + A (ω̄ × p_BoBr).
    s.p_WBr = init.p_WBo + R_WB * b.p_BoBr_B();
    s.v_WBr = b.is_free() ? Eigen::Vector3d(init.v_WBo + R_WB * init.w_WB_B.cross(b.p_BoBr_B()))
                          : Eigen::Vector3d::Zero();
    const Eigen::Index n = b.mode_count();
    s.q_f = Eigen::VectorXd::Zero(n);
    s.qd_f = Eigen::VectorXd::Zero(n);
    if (b.is_flexible()) {
      const FlexiblePart& f = *b.description().flexible;
      if (f.q0.size() == n) s.q_f = f.q0;
      if (f.qd0.size() == n) s.qd_f = f.qd0;
    }
  }
  apply_prescribed_motion(0.0, state);
  return state;
}

State Model::initial_state() const { return initial_state_; }

int Model::body_index(const std::string& name) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].name() == name) return static_cast<int>(i);
  }
  return -1;
}

Accelerations Model::make_accelerations() const {
  Accelerations acc(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    acc[i].qdd_f = Eigen::VectorXd::Zero(bodies_[i].mode_count());
  }
  return acc;
}

void Model::apply_prescribed_motion(double t, State& state) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (!b.is_prescribed()) continue;
    const RigidBodyDescription& d = b.description();
    const PrescribedAttitude law = prescribed_attitude(d.prescribed, d.initial.theta_WB, t);
    BodyState& s = state[i];
    s.p_WBr = d.initial.p_WBo;  // Br = Bo, fixed on the axis
    s.v_WBr.setZero();
    s.theta_WB = law.theta_WB;
    s.w_WB_B = law.w_WB_B;
  }
}

Workspace Model::make_workspace() const {
  Workspace ws;
  ws.kinematics.resize(bodies_.size());
  ws.wrenches.resize(bodies_.size());
  ws.flexible.resize(bodies_.size());
  ws.wear.resize(wear_names_.size());
  if (constraints_) {
    ws.constraint = ConstraintSolveTpl<double>(constraints_->row_count(), layout_, active_rows_);
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    ws.kinematics[i].p_BoBr_B = b.p_BoBr_B();
    const Eigen::Index n = b.mode_count();
    ws.wrenches[i].Q_f = Eigen::VectorXd::Zero(n);
    // The rows driving_torque evaluates (rigid prescribed bodies too).
    ws.flexible[i].residual = Eigen::VectorXd::Zero(6 + n);
    if (!b.is_flexible()) continue;
    ws.kinematics[i].invariants = &b.invariants();
    FlexibleScratch& fs = ws.flexible[i];
    fs.terms = flexible::make_inertia_terms(static_cast<int>(n));
    fs.solve = flexible::make_mass_solve_scratch(static_cast<int>(n));
    fs.rhs = Eigen::VectorXd::Zero(6 + n);
    fs.x = Eigen::VectorXd::Zero(6 + n);
    fs.zero = Eigen::VectorXd::Zero(n);
  }
  return ws;
}

void Model::pose_bodies(const State& state, Workspace& ws) const {
  // Loads see the state's q_f under the coupled model, q_f = 0 under LTE (undeformed body).
  const bool lte = formulation_ == FlexibleFormulation::kLte;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    ws.kinematics[i].state = &state[i];
    ws.kinematics[i].R_WB = rotation::rotation_matrix(state[i].theta_WB);
    ws.kinematics[i].q_f = lte ? &ws.flexible[i].zero : &state[i].q_f;
  }
}

void Model::compute_wrenches(const LoadContext& context, const State& state, Workspace& ws) const {
  ws.time = context.t;
  pose_bodies(state, ws);
  for (Wrench& w : ws.wrenches) w.set_zero();
  for (const auto& e : elements_) e->add_wrenches(context, ws.kinematics, ws.wrenches);
}

void Model::flexible_system(int i, const BodyState& s, Workspace& ws) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system_tpl<double>(b.invariants(), formulation_, ws.kinematics[k].R_WB, s, fs.zero,
                              ws.wrenches[k], b.modal_stiffness(), b.modal_damping(), fs.terms,
                              fs.rhs);
}

Eigen::Vector3d Model::prescribed_alpha_WB_B(const Body& b, double t) const {
  if (!b.is_prescribed()) return Eigen::Vector3d::Zero();
  const RigidBodyDescription& d = b.description();
  return prescribed_attitude(d.prescribed, d.initial.theta_WB, t).alpha_WB_B;
}

void Model::flexible_accelerations(int i, const BodyState& s, Workspace& ws,
                                   BodyAcceleration& a) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  solve_flexible_accelerations_tpl<double>(b.modal_mass(), formulation_, fs.terms, b.motion(),
                                           prescribed_alpha_WB_B(b, ws.time), fs.rhs, fs.solve,
                                           fs.x);
  a.a_WBr = fs.x.head<3>();
  a.alpha_WB_B = fs.x.segment<3>(3);
  a.qdd_f = fs.x.tail(n);
}

void Model::accelerations_from_wrenches(const State& state, Workspace& ws,
                                        Accelerations& accelerations) const {
  free_accelerations(state, ws, accelerations);
  if (constraints_) apply_constraints(ws.time, ws, accelerations);
}

void Model::free_accelerations(const State& state, Workspace& ws,
                               Accelerations& accelerations) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (b.is_flexible()) {
      flexible_accelerations(static_cast<int>(i), state[i], ws, accelerations[i]);
      continue;
    }
    BodyAcceleration& a = accelerations[i];
    rigid_body_accelerations_tpl<double>(b.motion(), b.mass(), b.I_Br_B(), b.I_Br_B_inverse(),
                                         ws.kinematics[i].R_WB, ws.wrenches[i], state[i].w_WB_B,
                                         prescribed_alpha_WB_B(b, ws.time), a.a_WBr, a.alpha_WB_B);
  }
}

void Model::compute_accelerations(const LoadContext& context, const State& state, Workspace& ws,
                                  Accelerations& accelerations) const {
  compute_wrenches(context, state, ws);
  accelerations_from_wrenches(state, ws, accelerations);
}

void Model::dynamics_residual(int i, const BodyState& s, const BodyAcceleration& acc, Workspace& ws,
                              Eigen::Ref<Eigen::VectorXd> out) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  const Wrench& w = ws.wrenches[k];
  const Eigen::Matrix3d& R_WB = ws.kinematics[k].R_WB;
  if (!b.is_flexible()) {
    // m a − f;  I α̅ + ω̄ × I ω̄ − Aᵀ τ   (about Br)
    out.head<3>() = b.mass() * acc.a_WBr - w.f_W;
    out.segment<3>(3) = b.I_Br_B() * acc.alpha_WB_B + s.w_WB_B.cross(b.I_Br_B() * s.w_WB_B) -
                        R_WB.transpose() * w.tau_Br_W;
    return;
  }
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  const flexible::InertiaTerms& t = fs.terms;
  // M x − rhs by blocks: [M_rr x_r + M_rf x_f; M_rfᵀ x_r + m_ff x_f] (LTE: no M_rf x_f in the
  // rigid rows).
  fs.x.head<3>() = acc.a_WBr;
  fs.x.segment<3>(3) = acc.alpha_WB_B;
  fs.x.tail(n) = acc.qdd_f;
  out = -fs.rhs;
  out.head<6>().noalias() += t.M_rr * fs.x.head<6>();
  if (n == 0) return;
  if (formulation_ == FlexibleFormulation::kCoupled) {
    out.head<6>().noalias() += t.M_rf * fs.x.tail(n);
  }
  out.tail(n).noalias() += t.M_rf.transpose() * fs.x.head<6>();
  out.tail(n).noalias() += b.invariants().m_ff * fs.x.tail(n);
}

void Model::residual_mass_matrix(int i, const Workspace& ws,
                                 Eigen::Ref<Eigen::MatrixXd> out) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  const flexible::InertiaTerms& t = ws.flexible[k].terms;
  const Eigen::Index n = b.mode_count();
  out.topLeftCorner<6, 6>() = t.M_rr;
  if (n == 0) return;
  if (formulation_ == FlexibleFormulation::kCoupled) {
    out.topRightCorner(6, n) = t.M_rf;
  } else {
    out.topRightCorner(6, n).setZero();
  }
  out.bottomLeftCorner(n, 6) = t.M_rf.transpose();
  out.bottomRightCorner(n, n) = b.invariants().m_ff;
}

void Model::modal_accelerations(int i, const BodyState& s, const Eigen::Vector3d& a_WBr,
                                const Eigen::Vector3d& alpha_WB_B, Workspace& ws,
                                Eigen::VectorXd& qdd_f) const {
  const auto k = static_cast<std::size_t>(i);
  const Body& b = bodies_[k];
  FlexibleScratch& fs = ws.flexible[k];
  flexible_system(i, s, ws);
  const Eigen::Index n = b.mode_count();
  if (b.is_prescribed()) {
    fs.x.head<3>().setZero();
    fs.x.segment<3>(3) = prescribed_alpha_WB_B(b, ws.time);
  } else {
    fs.x.head<3>() = a_WBr;
    fs.x.segment<3>(3) = alpha_WB_B;
  }
  flexible::solve_modal_rows(b.modal_mass(), fs.terms, fs.rhs, fs.solve, fs.x);
  qdd_f = fs.x.tail(n);
}

double Model::driving_torque(int i, const BodyState& s, const BodyAcceleration& acc,
                             Workspace& ws) const {
  const Body& b = body(i);
  if (!b.is_prescribed()) return 0.0;
  FlexibleScratch& fs = ws.flexible[static_cast<std::size_t>(i)];
  dynamics_residual(i, s, acc, ws, fs.residual);
  // The drive's torque τ_d enters the rotation rows as +Aᵀ τ_d, so τ_d,B = the residual there.
  const Eigen::Vector3d tau_drive_W =
      ws.kinematics[static_cast<std::size_t>(i)].R_WB * fs.residual.segment<3>(3);
  return b.description().prescribed.axis_W.dot(tau_drive_W);
}

double Model::kinetic_energy(const State& state) const {
  double t = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    if (b.is_flexible()) {
      t += flexible::flexible_kinetic_energy(b.invariants(), rotation::rotation_matrix(s.theta_WB),
                                             s.q_f, s.v_WBr, s.w_WB_B, s.qd_f);
      continue;
    }
    // T = ½ m |v_Bcm|² + ½ ω̄ᵀ I_Bcm ω̄ (free, Br = Bcm);  T = ½ ω̄ᵀ I_Pv ω̄ (pivot).
    t += 0.5 * s.w_WB_B.dot(b.I_Br_B() * s.w_WB_B);
    if (b.is_free()) t += 0.5 * b.mass() * s.v_WBr.squaredNorm();
  }
  return t;
}

double Model::potential_energy(const LoadContext& context, const State& state,
                               Workspace& ws) const {
  pose_bodies(state, ws);
  double v = elastic_energy(state);
  for (const auto& e : elements_) v += e->potential_energy(context, ws.kinematics);
  return v;
}

void Model::switching_functions(const LoadContext& context, const State& state, Workspace& ws,
                                std::span<double> g) const {
  pose_bodies(state, ws);
  std::size_t offset = 0;
  for (const auto& e : elements_) {
    const auto count = static_cast<std::size_t>(e->switching_function_count());
    if (count == 0) continue;
    e->switching_functions(context, ws.kinematics, g.subspan(offset, count));
    offset += count;
  }
}

double Model::dissipated_power(const LoadContext& context, const State& state,
                               Workspace& ws) const {
  pose_bodies(state, ws);
  double p = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].is_flexible()) {
      // q̇_fᵀ D q̇_f with D = diag(d_i)
      p += state[i].qd_f.dot(bodies_[i].modal_damping().cwiseProduct(state[i].qd_f));
    }
  }
  for (const auto& e : elements_) p += e->dissipated_power(context, ws.kinematics);
  return p;
}

double Model::elastic_energy(const State& state) const {
  double v = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (!bodies_[i].is_flexible()) continue;
    // ½ q_fᵀ K q_f with K = diag(K_i)
    v += 0.5 * state[i].q_f.dot(bodies_[i].modal_stiffness().cwiseProduct(state[i].q_f));
  }
  return v;
}

Eigen::Vector3d Model::linear_momentum_W(const State& state) const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyState& s = state[i];
    const Eigen::Matrix3d R_WB = rotation::rotation_matrix(s.theta_WB);
    if (b.is_flexible()) {
      // First row of M v: m Ṙ + A (ω̄ × s_t + S q̇_f)
      const flexible::ModalInvariants& inv = b.invariants();
      p += inv.mass * s.v_WBr + R_WB * (s.w_WB_B.cross(flexible::first_moment(inv, s.q_f)) +
                                        flexible::first_moment_rate(inv, s.q_f, s.qd_f));
      continue;
    }
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
    const Eigen::Matrix3d R_WB = rotation::rotation_matrix(s.theta_WB);
    if (b.is_flexible()) {
      // H_O = p_WBr × p + H_Br,  H_Br = A (s̃_t Aᵀ Ṙ + Ī_θθ ω̄ + Ī_θf q̇_f)  (θ row of M v)
      const flexible::ModalInvariants& inv = b.invariants();
      const Eigen::Vector3d s_t = flexible::first_moment(inv, s.q_f);
      const Eigen::Vector3d p_W =
          inv.mass * s.v_WBr +
          R_WB * (s.w_WB_B.cross(s_t) + flexible::first_moment_rate(inv, s.q_f, s.qd_f));
      const Eigen::Vector3d h_B = s_t.cross(R_WB.transpose() * s.v_WBr) +
                                  flexible::inertia_theta_theta(inv, s.q_f) * s.w_WB_B +
                                  flexible::inertia_theta_f(inv, s.q_f) * s.qd_f;
      h += s.p_WBr.cross(p_W) + R_WB * h_B;
      continue;
    }
    const Eigen::Vector3d v_WBcm = s.v_WBr + R_WB * s.w_WB_B.cross(b.p_BrBcm_B());
    h += s.p_WBr.cross(b.mass() * v_WBcm) + R_WB * (b.I_Br_B() * s.w_WB_B);
  }
  return h;
}

Eigen::Vector3d Model::p_WBo(int i, const BodyState& s) const {
  return s.p_WBr - rotation::rotation_matrix(s.theta_WB) * body(i).p_BoBr_B();
}

Eigen::Vector3d Model::v_WBo(int i, const BodyState& s) const {
  return s.v_WBr - rotation::rotation_matrix(s.theta_WB) * s.w_WB_B.cross(body(i).p_BoBr_B());
}

Eigen::Vector3d Model::p_WP(int i, const BodyState& s, const Eigen::Vector3d& p_BoP_B) const {
  return s.p_WBr + rotation::rotation_matrix(s.theta_WB) * (p_BoP_B - body(i).p_BoBr_B());
}

Eigen::Vector3d Model::p_WP(int i, const BodyState& s, const TrackedPoint& point) const {
  return s.p_WBr + rotation::rotation_matrix(s.theta_WB) * body(i).p_BrP_B(point, s.q_f);
}

// --- Ideal joints (docs/joints.md, "Ideal joints") ----------------------------------------

void Model::apply_inverse_mass(int b, const Eigen::Ref<const Eigen::VectorXd>& rhs,
                               Eigen::Ref<Eigen::VectorXd> out, Workspace& ws) const {
  const auto k = static_cast<std::size_t>(b);
  const Body& body = bodies_[k];
  if (body.is_flexible()) {
    FlexibleScratch& fs = ws.flexible[k];
    fs.x.head<6>().setZero();  // the known rows take no constraint force
    if (formulation_ == FlexibleFormulation::kCoupled) {
      flexible::apply_coupled_tpl<double>(body.modal_mass(), fs.terms, rhs, fs.solve, fs.x);
    } else {
      flexible::apply_lte_tpl<double>(body.modal_mass(), fs.terms, rhs, fs.solve, fs.x);
    }
    out = fs.x;
    return;
  }
  // Rigid, about Br: M = diag(m 1, I_Br) on (v_WBr, ω̄); a pivot's translation and a prescribed
  // body's motion are fixed.
  out.setZero();
  if (body.is_prescribed()) return;
  if (body.is_free()) out.head<3>() = rhs.head<3>() / body.mass();
  out.segment<3>(3).noalias() = body.I_Br_B_inverse() * rhs.segment<3>(3);
}

void Model::stack_velocities(const State& state, Eigen::VectorXd& v) const {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const int o = layout_.offset(static_cast<int>(b));
    v.segment<3>(o) = state[b].v_WBr;
    v.segment<3>(o + 3) = state[b].w_WB_B;
    v.segment(o + 6, bodies_[b].mode_count()) = state[b].qd_f;
  }
}

void Model::apply_constraints(double t, Workspace& ws, Accelerations& accelerations) const {
  ConstraintSolveTpl<double>& s = ws.constraint;
  constraints_->evaluate(t, ws.kinematics, layout_, s.rows);
  if (ws.constraint_stabilization > 0.0) {
    // Baumgarte: γ − 2α (J v + Φ_t) − α² Φ (critically damped drift at the rate α).
    const double alpha = ws.constraint_stabilization;
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const int o = layout_.offset(static_cast<int>(b));
      const BodyState& x = *ws.kinematics[b].state;
      s.v.segment<3>(o) = x.v_WBr;
      s.v.segment<3>(o + 3) = x.w_WB_B;
      s.v.segment(o + 6, bodies_[b].mode_count()) = x.qd_f;
    }
    add_baumgarte(alpha, s);
  }
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const int o = layout_.offset(static_cast<int>(b));
    s.x.segment<3>(o) = accelerations[b].a_WBr;
    s.x.segment<3>(o + 3) = accelerations[b].alpha_WB_B;
    s.x.segment(o + 6, bodies_[b].mode_count()) = accelerations[b].qdd_f;
  }
  solve_constrained_accelerations(
      *constraints_, layout_,
      [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out, ws); }, t, s);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const int o = layout_.offset(static_cast<int>(b));
    accelerations[b].a_WBr = s.x.segment<3>(o);
    accelerations[b].alpha_WB_B = s.x.segment<3>(o + 3);
    accelerations[b].qdd_f = s.x.segment(o + 6, bodies_[b].mode_count());
  }
}

void Model::factor_constraints_at(double t, const State& state, Workspace& ws) const {
  ws.time = t;
  pose_bodies(state, ws);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (!b.is_flexible()) continue;
    // The mass matrix at the state (its loads do not enter the factors).
    flexible_system(static_cast<int>(i), state[i], ws);
    FlexibleScratch& fs = ws.flexible[i];
    if (formulation_ == FlexibleFormulation::kCoupled) {
      flexible::factor_coupled_tpl<double>(b.modal_mass(), fs.terms, known_rows(b.motion()),
                                           fs.solve);
    } else {
      flexible::factor_lte_tpl<double>(fs.terms, known_rows(b.motion()), fs.solve);
    }
  }
  ConstraintSolveTpl<double>& s = ws.constraint;
  constraints_->evaluate(t, ws.kinematics, layout_, s.rows);
  if (!factor_or_reselect(
          *constraints_, layout_,
          [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out, ws); }, s)) {
    throw_singular(*constraints_, s, t);
  }
}

void Model::check_singular_configuration(double t, const State& state, Workspace& ws) const {
  factor_constraints_at(t, state, ws);
  check_orientation(
      *constraints_, layout_,
      [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out, ws); }, t,
      ws.constraint);
}

Model::RelativeViolation Model::relative_violation(ConstraintSolveTpl<double>& s,
                                                   const State& state) const {
  const ConstraintRows& rows = s.rows;
  stack_velocities(state, s.v);
  s.rate.noalias() = rows.J * s.v;
  s.rate += rows.phi_t;
  const Eigen::VectorXd& rate = s.rate;
  // Velocity scale: the bodies' speeds (|v_Br| + |ω̄| ℓ) and the drives' rates.
  double speed = 0.0;
  for (const BodyState& b : state) {
    speed = std::max(speed, b.v_WBr.norm() + b.w_WB_B.norm() * joint_length_scale_);
  }
  for (Eigen::Index r = 0; r < rows.phi_t.size(); ++r) {
    const double scale =
        constraints_->is_length_row(static_cast<int>(r)) ? 1.0 : joint_length_scale_;
    speed = std::max(speed, std::abs(rows.phi_t(r)) * scale);
  }
  RelativeViolation out;
  for (Eigen::Index r = 0; r < rows.phi.size(); ++r) {
    const int row = static_cast<int>(r);
    const bool length = constraints_->is_length_row(row);
    const double position = std::abs(rows.phi(r)) / (length ? joint_length_scale_ : 1.0);
    const double velocity =
        speed > 0.0 ? std::abs(rate(r)) * (length ? 1.0 : joint_length_scale_) / speed : 0.0;
    if (position > out.position) {
      out.position = position;
      out.position_joint = constraints_->joint_of_row(row);
    }
    if (velocity > out.velocity) {
      out.velocity = velocity;
      out.velocity_joint = constraints_->joint_of_row(row);
    }
  }
  return out;
}

InitialProjection Model::project(double t, State& state, Workspace& ws) const {
  InitialProjection before;
  if (!constraints_) return before;
  ConstraintSolveTpl<double>& s = ws.constraint;
  factor_constraints_at(t, state, ws);
  const RelativeViolation first = relative_violation(s, state);
  before.position = first.position;
  // Newton on Φ = 0 in the mass metric: converged when the relative violation is a few ε (the
  // round-off of Φ itself, a sum of products of lengths of size ℓ).
  project_positions<double>(
      [&] { factor_constraints_at(t, state, ws); },
      [&] {
        return relative_position_violation<double>(*constraints_, s.rows.phi, joint_length_scale_);
      },
      [&](const Eigen::VectorXd& delta) {
        for (std::size_t b = 0; b < bodies_.size(); ++b) {
          const Body& body = bodies_[b];
          if (body.is_prescribed() && !body.is_flexible()) continue;
          const int o = layout_.offset(static_cast<int>(b));
          BodyState& x = state[b];
          if (!body.is_prescribed()) {
            x.p_WBr += delta.segment<3>(o);
            // A ← A exp(δφ̃): θ ← θ ⊗ exp(δφ), renormalized.
            x.theta_WB = rotation::quaternion_multiply(
                x.theta_WB, rotation::exp_quaternion(Eigen::Vector3d(delta.segment<3>(o + 3))));
            x.theta_WB.normalize();
          }
          x.q_f += delta.segment(o + 6, body.mode_count());
        }
      },
      8.0 * std::numeric_limits<double>::epsilon(), s);
  before.velocity = relative_violation(s, state).velocity;
  project_velocities(t, state, ws);
  return before;
}

void Model::project_velocities(double t, State& state, Workspace& ws) const {
  if (!constraints_) return;
  ConstraintSolveTpl<double>& s = ws.constraint;
  factor_constraints_at(t, state, ws);
  stack_velocities(state, s.v);
  s.rate.noalias() = s.rows.J * s.v;
  s.rate += s.rows.phi_t;
  constraint_correction<double>(s.rate, s);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    const int o = layout_.offset(static_cast<int>(b));
    BodyState& x = state[b];
    if (!body.is_prescribed()) {
      if (body.is_free()) x.v_WBr += s.x.segment<3>(o);
      x.w_WB_B += s.x.segment<3>(o + 3);
    }
    x.qd_f += s.x.segment(o + 6, body.mode_count());
  }
}

void Model::assemble_initial_state(const ConstraintOptions& options) {
  Workspace ws = make_workspace();
  pose_bodies(initial_state_, ws);
  ConstraintRows rows;
  rows.resize(constraints_->row_count(), layout_.size());
  constraints_->evaluate(0.0, ws.kinematics, layout_, rows);
  active_rows_ = core::independent_rows<double>(rows.J);
  // The joints' length scale ℓ: the largest arm from a body's Br to a joint point.
  joint_length_scale_ = core::joint_length_scale<double>(*constraints_, layout_, rows.J);
  ws = make_workspace();
  State state = initial_state_;
  ws.constraint.rows = rows;
  const RelativeViolation before = relative_violation(ws.constraint, state);
  const auto refuse = [&](int joint, const char* level, double value) {
    throw InconsistentInitialStateError(
        joint, "the initial state violates joint '" + constraints_->joint_name(joint) + "' at " +
                   level + " level by " + std::to_string(value) +
                   " (relative), more than the accepted " +
                   std::to_string(options.initial_tolerance) +
                   "; correct the bodies' initial positions and velocities, or set "
                   "project_initial_state = true in [scene] to project them onto the joints");
  };
  if (!options.project_initial_state && before.position > options.initial_tolerance) {
    refuse(before.position_joint, "position", before.position);
  }
  initial_projection_ = project(0.0, state, ws);
  if (!options.project_initial_state && initial_projection_.velocity > options.initial_tolerance) {
    refuse(before.velocity_joint, "velocity", initial_projection_.velocity);
  }
  initial_state_ = std::move(state);
}

std::vector<std::array<double, 2>> Model::constraint_violations(double t, const State& state,
                                                                Workspace& ws) const {
  std::vector<std::array<double, 2>> out;
  if (!constraints_) return out;
  ws.time = t;
  pose_bodies(state, ws);
  ConstraintRows& rows = ws.constraint.rows;
  constraints_->evaluate(t, ws.kinematics, layout_, rows);
  Eigen::VectorXd v(layout_.size());
  stack_velocities(state, v);
  return joint_violations<double>(*constraints_, rows, v);
}

std::vector<JointReaction> Model::joint_reactions(const LoadContext& context, const State& state,
                                                  Workspace& ws) const {
  std::vector<JointReaction> out;
  if (!constraints_) return out;
  Accelerations accelerations = make_accelerations();
  // Outputs come at any spacing: the rows' orientation test (core/constrained_solve_tpl.hpp),
  // which assumes the small state changes between a solver's evaluations, does not apply.
  ws.constraint.has_previous = false;
  compute_accelerations(context, state, ws, accelerations);
  return joint_reactions_from_solve<double>(*constraints_, ws.kinematics, layout_, ws.constraint);
}

}  // namespace flexref::core
