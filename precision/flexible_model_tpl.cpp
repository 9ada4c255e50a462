#include "precision/flexible_model_tpl.hpp"

// Eigen's NumTraits for float128 before any Eigen type of it.
#include <algorithm>
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>
#include <cmath>
#include <stdexcept>

#include "contact/contact.hpp"
#include "contact/contact_point_tpl.hpp"
#include "contact/gap_support.hpp"
#include "core/unit_vector_tpl.hpp"
#include "precision/refusal.hpp"
#include "reference/exact_rotation_tpl.hpp"
#include "scene/build_model.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::precision {
namespace {

template <typename S>
Eigen::Matrix<S, 3, 3> rotation_of(const Eigen::Matrix<S, 4, 1>& q) {
  // A(θ/|θ|) for Euler parameters of any norm (model.md eq. (1)).
  const S s = S(2) / q.squaredNorm();
  const S e0 = q(0), e1 = q(1), e2 = q(2), e3 = q(3);
  Eigen::Matrix<S, 3, 3> A;
  A << S(1) - s * (e2 * e2 + e3 * e3), s * (e1 * e2 - e0 * e3), s * (e1 * e3 + e0 * e2),
      s * (e1 * e2 + e0 * e3), S(1) - s * (e1 * e1 + e3 * e3), s * (e2 * e3 - e0 * e1),
      s * (e1 * e3 - e0 * e2), s * (e2 * e3 + e0 * e1), S(1) - s * (e1 * e1 + e2 * e2);
  return A;
}

}  // namespace

template <typename S>
bool FlexibleModelTpl<S>::applies_to(const scene::SceneSpec& spec) {
  return std::any_of(spec.bodies.begin(), spec.bodies.end(),
                     [](const scene::BodySpec& b) { return b.description.flexible.has_value(); });
}

template <typename S>
FlexibleModelTpl<S>::FlexibleModelTpl(const scene::SceneSpec& spec,
                                      core::FlexibleFormulation formulation)
    : formulation_(formulation), g_W_(spec.g_W.cast<S>()) {
  const auto refuse = [&](const scene::SpecSource& source, const std::string& what) {
    refuse_part(spec, source, what,
                "of a flexible body yet (docs/precision.md: one flexible body, free, pivot or "
                "prescribed, with gravity, applied forces and torques, point-charge potentials, "
                "gap supports and spheres on ground planes)");
  };
  if (spec.bodies.size() != 1) {
    refuse(spec.bodies.at(1).source, "a flexible body with another body");
  }
  for (const scene::ContactSpec& c : spec.contacts) {
    for (const contact::ContactPair& pair : c.pairs) {
      if (pair.kind != contact::ContactPair::Kind::kSpherePlane) {
        refuse(c.source, "a sphere–sphere contact");
      }
    }
  }
  for (const scene::JointSpec& j : spec.joints) refuse(j.source, "a joint");
  const scene::BodySpec& body = spec.bodies.front();
  const core::RigidBodyDescription& d = body.description;
  if (!d.flexible) throw std::invalid_argument(spec.name + ": the body is not flexible");
  const flexible::ModalData& modal = d.flexible->modal;
  modal.validate();
  name_ = d.name;
  motion_ = d.motion;
  prescribed_ = d.prescribed;
  axis_W_ = core::unit_vector_in<S>(d.prescribed.axis_W);
  n_ = modal.mode_count();

  // Invariants about Bo (nodes, then the hub) for the undeformed centre of mass; then about Br
  // (core/body.cpp's construction, every sum and shift in S).
  const Vector3 hub_c = d.p_BoBcm_B.cast<S>();
  const Eigen::Matrix3d I_sym_d = 0.5 * (d.I_Bcm_B + d.I_Bcm_B.transpose());
  const Matrix3 I_hub = I_sym_d.cast<S>();
  const flexible::GeometricStiffness* geometric = modal.geometric ? &*modal.geometric : nullptr;
  flexible::ModalInvariantsTpl<S> about_Bo =
      flexible::modal_invariants_tpl<S>(modal.mass, modal.p_BoNode_B, modal.phi, nullptr);
  flexible::add_rigid_part_tpl<S>(about_Bo, S(d.mass), hub_c, I_hub);
  switch (d.motion) {
    case core::MotionKind::kFree:
      p_BoBr_B_ = about_Bo.s0 / about_Bo.mass;
      break;
    case core::MotionKind::kPivot:
      p_BoBr_B_ = d.p_BoPivot_B.cast<S>();
      break;
    case core::MotionKind::kPrescribed:
      p_BoBr_B_.setZero();
      break;
  }
  // About Br: the nodes and the geometric matrices moved to Br in S.
  invariants_ = flexible::modal_invariants_tpl<S>(modal.mass, modal.p_BoNode_B, modal.phi,
                                                  geometric, p_BoBr_B_);
  flexible::add_rigid_part_tpl<S>(invariants_, S(d.mass), Vector3(hub_c - p_BoBr_B_), I_hub);
  factor_ = flexible::ModalMassFactorTpl<S>(invariants_);
  stiffness_ = modal.stiffness.cast<S>();
  damping_.resize(n_);
  for (int i = 0; i < n_; ++i) {
    using std::sqrt;
    // d_i = 2 ζ_i √(K_i μ_i), μ_i = (m_ff)_ii (flexible::modal_damping).
    damping_(i) = S(2) * S(modal.damping_ratio(i)) * sqrt(stiffness_(i) * invariants_.m_ff(i, i));
  }

  // Initial state (core::Model::initial_state): θ normalized in S; p_WBr = p_WBo + A p_BoBr;
  // v_WBr = v_WBo + A (ω̄ × p_BoBr) (zero for a pivot).
  const core::BodyInitialState& init = d.initial;
  theta0_ = init.theta_WB.cast<S>();
  {
    using std::sqrt;
    theta0_ /= sqrt(theta0_.squaredNorm());
  }
  const Matrix3 A0 = rotation_of<S>(theta0_);
  const Vector3 w0 = init.w_WB_B.cast<S>();
  p_WBo0_ = init.p_WBo.cast<S>();
  if (!prescribed()) {
    const Vector3 p_WBr = init.p_WBo.cast<S>() + A0 * p_BoBr_B_;
    const Vector3 v_WBr = d.motion == core::MotionKind::kPivot
                              ? Vector3::Zero().eval()
                              : Vector3(init.v_WBo.cast<S>() + A0 * w0.cross(p_BoBr_B_));
    initial_ = {p_WBr(0), p_WBr(1), p_WBr(2), theta0_(0), theta0_(1), theta0_(2), theta0_(3),
                v_WBr(0), v_WBr(1), v_WBr(2), w0(0),      w0(1),      w0(2)};
  }
  for (int i = 0; i < n_; ++i) {
    initial_.push_back(d.flexible->q0.size() == 0 ? S(0) : S(d.flexible->q0(i)));
  }
  for (int i = 0; i < n_; ++i) {
    initial_.push_back(d.flexible->qd0.size() == 0 ? S(0) : S(d.flexible->qd0(i)));
  }

  const auto attachment = [&](const Eigen::Vector3d& p_BoP_B, int node) {
    Attachment a;
    a.p_BrP_B = p_BoP_B.cast<S>() - p_BoBr_B_;
    a.node = node;
    if (node >= 0) a.phi_B = modal.mode_rows(node).template cast<S>();
    return a;
  };
  for (const core::TrackedPoint& p : d.points) points_.push_back(attachment(p.p_BoP_B, p.node));
  for (const scene::LoadSpec& l : spec.loads) {
    Load load;
    load.torque = l.torque;
    load.value = l.value.cast<S>();
    load.world_frame = l.frame == core::LoadFrame::kWorld;
    // The point as the spec gives it (the scene reader puts a node's load at the node), moved
    // by Φ_k q_f when it is attached to node k (core::AppliedForce).
    load.at = attachment(l.p_BoP_B, l.node);
    load.profile = l.profile;
    // W_a, once a harmonic force makes the model track it, is the work of every applied force
    // (core::Model::integral_rates sums AppliedForce::applied_power over all of them).
    load.tracks_work = !l.torque;
    loads_.push_back(load);
  }

  // The double model of the same spec gives the outputs and its discontinuities.
  const core::Model built = scene::build_model(spec, formulation);
  columns_ = studies::trajectory_columns(built);
  dissipates_ = built.dissipates();
  applied_work_ = dissipates_ && built.tracks_applied_work();
  integral_count_ = dissipates_ ? 1 + built.extra_integral_count() : 0;
  discontinuities_ = built.discontinuities();
  if (prescribed() && prescribed_.law.kind == core::AngleLaw::Kind::kSpinUp) {
    discontinuities_.push_back(prescribed_.law.spin_up_time);
  }
  std::sort(discontinuities_.begin(), discontinuities_.end());
  discontinuities_.erase(std::unique(discontinuities_.begin(), discontinuities_.end()),
                         discontinuities_.end());
  for (int k = 0; k < integral_count_; ++k) initial_.push_back(S(0));

  // The gap supports and sphere–plane pairs as the double model builds them (the laws'
  // parameters, the normalized axis and plane normals, the points' undeformed positions), in
  // its element order, which numbers the switching functions: every precision solves one model.
  wear_channels_ = built.wear_channel_names();
  const auto channel_of = [&](const core::ForceElement& element) {
    if (element.wear_channel_count() == 0) return -1;
    return static_cast<int>(
        std::find(wear_channels_.begin(), wear_channels_.end(), element.wear_channel_name()) -
        wear_channels_.begin());
  };
  for (const auto& element : built.elements()) {
    if (const auto* g = dynamic_cast<const contact::GapSupport*>(element.get())) {
      Support c;
      c.at = attachment(g->p_BoN_B(), g->node().deforms() ? g->node().node : -1);
      c.geometry = g->template geometry_in<S>();
      c.normal = g->normal_law();
      c.friction = g->friction_law();
      c.channel = channel_of(*g);
      supports_.push_back(c);
    } else if (const auto* e = dynamic_cast<const contact::ContactElement*>(element.get())) {
      for (const contact::ContactPair& pair : e->pairs()) {
        Support c;
        c.sphere = true;
        c.at = attachment(pair.p_BoCb_B, pair.node_b.deforms() ? pair.node_b.node : -1);
        c.radius = S(pair.radius_b);
        c.p_WQ = pair.p_WQ.cast<S>();
        c.n_W = core::unit_vector_in<S>(pair.n_W);
        c.normal = e->normal_law();
        c.friction = e->friction_law();
        c.channel = channel_of(*e);
        supports_.push_back(c);
      }
    }
  }
  // The potentials' charges sit at hub points (scene/load_reader.cpp): the frame's, never a
  // node's.
  for (const scene::PotentialSpec& spec_potential : spec.potentials) {
    Potential potential{core::PointChargePotential(spec_potential.alpha, spec_potential.beta,
                                                   spec_potential.p_WM, spec_potential.charges),
                        {}};
    for (const core::PointChargePotential::Charge& charge : spec_potential.charges) {
      potential.at.push_back(attachment(charge.p_BoP_B, -1));
    }
    potentials_.push_back(std::move(potential));
  }

  Scratch& s = scratch_;
  s.terms = flexible::make_inertia_terms_tpl<S>(n_);
  s.solve = flexible::make_mass_solve_scratch_tpl<S>(n_);
  s.q = Vector::Zero(n_);
  s.qd = Vector::Zero(n_);
  s.zero = Vector::Zero(n_);
  s.Q_f = Vector::Zero(n_);
  s.rhs = Vector::Zero(6 + n_);
  s.x = Vector::Zero(6 + n_);
  s.wear_power.assign(wear_channels_.size(), S(0));
  s.switching.assign(2 * supports_.size(), S(0));
  energy0_ = energy(S(0), initial_);
}

template <typename S>
std::vector<double> FlexibleModelTpl<S>::discontinuities() const {
  return discontinuities_;
}

template <typename S>
std::vector<S> FlexibleModelTpl<S>::initial_state() const {
  return initial_;
}

template <typename S>
typename FlexibleModelTpl<S>::Pose FlexibleModelTpl<S>::pose(S t, const std::vector<S>& y) const {
  Pose p;
  p.alpha_B.setZero();
  if (prescribed()) {
    using std::cos;
    using std::sin;
    // θ(t) = q(φ a_W) ⊗ θ0; ω̄ = φ̇ Aᵀ a_W; α̅ = φ̈ Aᵀ a_W (core/prescribed_motion.hpp).
    const S phi = prescribed_.law.angle_in<S>(t);
    Quaternion q_axis;
    q_axis << cos(S(0.5) * phi), sin(S(0.5) * phi) * axis_W_;
    p.theta_WB = reference::detail::quaternion_multiply<S>(q_axis, theta0_);
    p.A = rotation_of<S>(p.theta_WB);
    const Vector3 axis_B = p.A.transpose() * axis_W_;
    p.w_B = prescribed_.law.angular_rate_in<S>(t) * axis_B;
    p.alpha_B = prescribed_.law.angular_acceleration_in<S>(t) * axis_B;
    p.p_WBr = p_WBo0_;  // Br = Bo, fixed on the axis
    p.v_WBr.setZero();
  } else {
    p.p_WBr = Vector3(y[0], y[1], y[2]);
    p.theta_WB = Quaternion(y[3], y[4], y[5], y[6]);
    p.A = rotation_of<S>(p.theta_WB);
    p.v_WBr = Vector3(y[7], y[8], y[9]);
    p.w_B = Vector3(y[10], y[11], y[12]);
  }
  return p;
}

template <typename S>
void FlexibleModelTpl<S>::load_modes(const std::vector<S>& y) const {
  const auto o = static_cast<std::size_t>(rigid_size());
  for (Eigen::Index i = 0; i < n_; ++i) {
    scratch_.q(i) = y[o + static_cast<std::size_t>(i)];
    scratch_.qd(i) = y[o + static_cast<std::size_t>(n_ + i)];
  }
}

template <typename S>
typename FlexibleModelTpl<S>::Vector3 FlexibleModelTpl<S>::first_moment(const Vector& q) const {
  // s_t = s0 + S q + Δs, Δs_c = −½ q·E_c q (GS-4), by columns (no temporary).
  Vector3 s_t = invariants_.s0 + invariants_.S * q;
  if (invariants_.geometric) {
    for (const int c : invariants_.geometric->E_nonzero) {
      const auto& E = invariants_.geometric->E[static_cast<std::size_t>(c)];
      S quadratic(0);
      for (Eigen::Index j = 0; j < n_; ++j) quadratic += q(j) * E.col(j).dot(q);
      s_t(c) -= S(0.5) * quadratic;
    }
  }
  return s_t;
}

template <typename S>
typename FlexibleModelTpl<S>::Vector3 FlexibleModelTpl<S>::attached_offset_W(const Attachment& a,
                                                                             const Pose& p) const {
  // A (x_P − p_BoBr + Φ_k q_f): an attachment always sees the state's deformation
  // (core/node_attachment.hpp), under LTE too.
  if (a.node < 0) return p.A * a.p_BrP_B;
  return p.A * (a.p_BrP_B + a.phi_B * scratch_.q);
}

template <typename S>
typename FlexibleModelTpl<S>::SupportPoint FlexibleModelTpl<S>::support_point(const Support& c,
                                                                              const Pose& p) const {
  // A gap support: contact/gap_support_tpl.hpp in S at the deformed node N (GapSupport::
  // evaluate's). A sphere: contact/contact_point_tpl.hpp's P = C − r n on the plane, C the
  // (deformed) centre (ContactElement::evaluate's).
  const Vector3 r_C = attached_offset_W(c.at, p);
  if (c.sphere) {
    const contact::ContactPointTpl<S> point =
        contact::sphere_plane_point_tpl<S>(Vector3(p.p_WBr + r_C), c.radius, c.p_WQ, c.n_W);
    return {point.gap, point.n_W, Vector3(point.p_WP - p.p_WBr)};
  }
  const contact::GapPointTpl<S> point =
      contact::gap_point_tpl<S>(c.geometry, Vector3(p.p_WBr + r_C));
  return {point.gap, point.n_W, r_C};
}

template <typename S>
typename FlexibleModelTpl<S>::SupportLoad FlexibleModelTpl<S>::support_load(const Support& c,
                                                                            const Pose& p) const {
  using std::abs;
  using std::sqrt;
  SupportLoad load;
  load.f_W.setZero();
  const SupportPoint point = support_point(c, p);
  const Vector3& n_W = point.n_W;
  load.gap = point.gap;
  load.r_W = point.r_W;
  // The material point's velocity at the point of application:
  // v_WBr + ω × (P − p_WBr) + A Φ_k q̇_f (core::attached_velocity_W).
  Vector3 v = p.v_WBr + (p.A * p.w_B).cross(load.r_W);
  if (c.at.node >= 0) v.noalias() += p.A * (c.at.phi_B * scratch_.qd);
  load.clamp = c.normal.clamp_function(S(-load.gap), S(-n_W.dot(v)));
  const contact::PenaltyLoadTpl<S> e =
      contact::penalty_load_tpl<S>(c.normal, c.friction, load.gap, n_W, v);
  load.dissipated_power = e.dissipated_power();
  if (!(e.normal.total > S(0))) return load;
  load.normal = e.normal.total;
  load.slip_speed = sqrt(e.v_t_W.squaredNorm());
  load.f_W = e.normal.total * n_W + e.f_friction_W;
  load.wear_power = abs(e.f_friction_W.dot(e.v_t_W));
  return load;
}

template <typename S>
typename FlexibleModelTpl<S>::ChargeLoad FlexibleModelTpl<S>::charge_load(
    const Potential& potential, std::size_t i, const Pose& p) const {
  // f_i = c_i (unit field at P_i), V_i = c_i V_unit(P_i), at the hub point P_i
  // (core/point_charge_potential.cpp).
  ChargeLoad charge;
  charge.r_W = attached_offset_W(potential.at[i], p);
  const Vector3 p_WP = p.p_WBr + charge.r_W;
  const S position[3] = {p_WP(0), p_WP(1), p_WP(2)};
  S field[3];
  S unit_potential;
  potential.law.unit_field(position, field, unit_potential);
  const S weight(potential.law.charges()[i].weight);
  charge.f_W = weight * Vector3(field[0], field[1], field[2]);
  charge.potential = weight * unit_potential;
  return charge;
}

template <typename S>
void FlexibleModelTpl<S>::switching_functions(S t, const std::vector<S>& y,
                                              std::vector<S>& values) const {
  load_modes(y);
  const Pose p = pose(t, y);
  values.resize(2 * supports_.size());
  for (std::size_t k = 0; k < supports_.size(); ++k) {
    const SupportLoad load = support_load(supports_[k], p);
    values[2 * k] = load.gap;
    values[2 * k + 1] = load.clamp;
  }
}

template <typename S>
void FlexibleModelTpl<S>::evaluate(S t, double t_segment, const Pose& p) const {
  Scratch& s = scratch_;
  const bool lte = formulation_ == core::FlexibleFormulation::kLte;
  // Loads see the state's q_f under the coupled model, q_f = 0 under LTE (core::Model).
  const Vector& q_load = lte ? s.zero : s.q;
  s.f_W.setZero();
  s.tau_W.setZero();
  s.Q_f.setZero();
  s.applied_power = S(0);
  if (g_W_(0) != S(0) || g_W_(1) != S(0) || g_W_(2) != S(0)) {
    // Qe_R += m g, Qe_θ: τ_Br_W += A (s_t × Aᵀ g), Qe_f += Sᵀ Aᵀ g − Σ_c (Aᵀg)_c E_c q_f
    // (core/gravity.cpp; the last term is the foreshortening's, geometric stiffening only).
    const Vector3 g_B = p.A.transpose() * g_W_;
    const Vector3 s_t = first_moment(q_load);
    if (invariants_.geometric) {
      for (const int c : invariants_.geometric->E_nonzero) {
        const auto& E = invariants_.geometric->E[static_cast<std::size_t>(c)];
        for (Eigen::Index j = 0; j < n_; ++j) s.Q_f.noalias() -= (g_B(c) * q_load(j)) * E.col(j);
      }
    }
    s.f_W += invariants_.mass * g_W_;
    s.tau_W += p.A * s_t.cross(g_B);
    s.Q_f.noalias() += invariants_.S.transpose() * g_B;
  }
  for (const Load& l : loads_) {
    const S scale = l.profile.value_in(t, t_segment);
    const Vector3 v = l.world_frame ? Vector3(scale * l.value) : Vector3(p.A * (scale * l.value));
    if (l.torque) {
      s.tau_W += v;
      continue;
    }
    // f, (P − p_WBr) × f and Φ_kᵀ Aᵀ f (core/node_attachment.hpp).
    const Vector3 r_W = attached_offset_W(l.at, p);
    s.f_W += v;
    s.tau_W += r_W.cross(v);
    if (l.at.node >= 0) s.Q_f.noalias() += l.at.phi_B.transpose() * (p.A.transpose() * v);
    if (l.tracks_work) {
      Vector3 v_P = p.v_WBr + (p.A * p.w_B).cross(r_W);
      if (l.at.node >= 0) v_P += p.A * (l.at.phi_B * s.qd);
      s.applied_power += v.dot(v_P);
    }
  }
  for (const Potential& potential : potentials_) {
    for (std::size_t i = 0; i < potential.at.size(); ++i) {
      const ChargeLoad charge = charge_load(potential, i, p);
      s.f_W += charge.f_W;
      s.tau_W += charge.r_W.cross(charge.f_W);
    }
  }
  s.contact_dissipation = S(0);
  std::fill(s.wear_power.begin(), s.wear_power.end(), S(0));
  for (std::size_t k = 0; k < supports_.size(); ++k) {
    // At the deformed node (a sphere: at P) under either model, as applied forces at nodes
    // (core::add_attached_force): f, r × f and Φ_kᵀ Aᵀ f.
    const Support& c = supports_[k];
    const SupportLoad load = support_load(c, p);
    s.switching[2 * k] = load.gap;
    s.switching[2 * k + 1] = load.clamp;
    s.contact_dissipation += load.dissipated_power;
    if (!(load.normal > S(0))) continue;
    s.f_W += load.f_W;
    s.tau_W += load.r_W.cross(load.f_W);
    if (c.at.node >= 0) s.Q_f.noalias() += c.at.phi_B.transpose() * (p.A.transpose() * load.f_W);
    if (c.channel >= 0) s.wear_power[static_cast<std::size_t>(c.channel)] += load.wear_power;
  }
  if (lte) {
    // The inertia terms of the undeformed body (q_f = 0, q̇_f = 0).
    flexible::set_undeformed_products_tpl<S>(s.terms);
    flexible::assemble_inertia_terms_tpl<S>(invariants_, p.A, s.zero, p.w_B, s.zero, s.terms);
  } else {
    flexible::compute_modal_products_tpl<S>(invariants_, s.q, s.qd, s.terms);
    flexible::assemble_inertia_terms_tpl<S>(invariants_, p.A, s.q, p.w_B, s.qd, s.terms);
  }
  const Vector& Qv = s.terms.Qv;
  s.rhs.template head<3>() = s.f_W + Qv.template head<3>();
  s.rhs.template segment<3>(3) = p.A.transpose() * s.tau_W + Qv.template segment<3>(3);
  s.rhs.tail(n_) = s.Q_f + Qv.tail(n_) - stiffness_.cwiseProduct(s.q) - damping_.cwiseProduct(s.qd);
  // Known rows: a = 0 (pivot, prescribed), α̅ of the law (prescribed).
  const int known = motion_ == core::MotionKind::kFree    ? 0
                    : motion_ == core::MotionKind::kPivot ? 3
                                                          : 6;
  s.x.setZero();
  s.x.template segment<3>(3) = p.alpha_B;
  if (lte) {
    flexible::factor_lte_tpl<S>(s.terms, known, s.solve);
    flexible::apply_lte_tpl<S>(factor_, s.terms, s.rhs, s.solve, s.x);
  } else {
    flexible::factor_coupled_tpl<S>(factor_, s.terms, known, s.solve);
    flexible::apply_coupled_tpl<S>(factor_, s.terms, s.rhs, s.solve, s.x);
  }
}

template <typename S>
void FlexibleModelTpl<S>::derivative(const std::vector<S>& y, std::vector<S>& dydt, S t,
                                     double t_segment, std::vector<S>* switching) const {
  Scratch& s = scratch_;
  const auto o = static_cast<std::size_t>(rigid_size());
  const auto n = static_cast<std::size_t>(n_);
  load_modes(y);
  const Pose p = pose(t, y);
  evaluate(t, t_segment, p);
  if (switching != nullptr) *switching = s.switching;
  dydt.resize(y.size());
  if (!prescribed()) {
    // ṗ = v; θ̇ = ½ θ ⊗ (0, ω̄); v̇ = a; ω̄̇ = α̅.
    const S h(0.5);
    const S e0 = y[3], e1 = y[4], e2 = y[5], e3 = y[6];
    const Vector3& w = p.w_B;
    for (std::size_t k = 0; k < 3; ++k) dydt[k] = y[7 + k];
    dydt[3] = -h * (e1 * w(0) + e2 * w(1) + e3 * w(2));
    dydt[4] = h * (e0 * w(0) + e2 * w(2) - e3 * w(1));
    dydt[5] = h * (e0 * w(1) + e3 * w(0) - e1 * w(2));
    dydt[6] = h * (e0 * w(2) + e1 * w(1) - e2 * w(0));
    for (std::size_t k = 0; k < 3; ++k) {
      dydt[7 + k] = s.x(static_cast<Eigen::Index>(k));
      dydt[10 + k] = s.x(static_cast<Eigen::Index>(3 + k));
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    dydt[o + i] = y[o + n + i];
    dydt[o + n + i] = s.x(6 + static_cast<Eigen::Index>(i));
  }
  if (dissipates_) {
    // Ẇ_d = q̇ᵀ D q̇ + the supports' dissipation; Ẇ_a = f·v_P; each wear channel's |F_t·v_t|.
    const std::size_t integrals = o + 2 * n;
    dydt[integrals] = s.qd.dot(damping_.cwiseProduct(s.qd)) + s.contact_dissipation;
    for (int k = 1; k < integral_count_; ++k) dydt[integrals + static_cast<std::size_t>(k)] = S(0);
    if (applied_work_) dydt[integrals + 1] = s.applied_power;
    const std::size_t first_wear = integrals + (applied_work_ ? 2 : 1);
    for (std::size_t c = 0; c < s.wear_power.size(); ++c) dydt[first_wear + c] = s.wear_power[c];
  }
}

template <typename S>
S FlexibleModelTpl<S>::energy(S t, const std::vector<S>& y) const {
  Scratch& s = scratch_;
  load_modes(y);
  const Pose p = pose(t, y);
  // T = ½ vᵀ M v, v = (v_WBr, ω̄, q̇_f), M at the state's q_f (core::Model::kinetic_energy, under
  // LTE too): ½ [v_rᵀ M_rr v_r + 2 v_rᵀ M_rf q̇ + q̇ᵀ m_ff q̇].
  flexible::compute_modal_products_tpl<S>(invariants_, s.q, s.zero, s.terms);
  flexible::assemble_inertia_terms_tpl<S>(invariants_, p.A, s.q, p.w_B, s.zero, s.terms);
  Eigen::Matrix<S, 6, 1> v_r;
  v_r << p.v_WBr, p.w_B;
  const S vMv = v_r.dot(s.terms.M_rr * v_r) + S(2) * v_r.dot(s.terms.M_rf * s.qd) +
                s.qd.dot(invariants_.m_ff * s.qd);
  // V = −g·(m p_WBr + A s_t) on the loads' q_f (zero under LTE) + ½ q_fᵀ K q_f.
  const bool lte = formulation_ == core::FlexibleFormulation::kLte;
  const Vector& q_load = lte ? s.zero : s.q;
  const Vector3 s_t = first_moment(q_load);
  S V = -g_W_.dot(invariants_.mass * p.p_WBr + p.A * s_t) +
        S(0.5) * s.q.dot(stiffness_.cwiseProduct(s.q));
  // The supports' and pairs' V_law(δ) at the deformed points (GapSupport's and
  // ContactElement's potential_energy).
  for (const Support& c : supports_) V += c.normal.potential_in(S(-support_point(c, p).gap));
  // Σ c_i V_unit(P_i) (PointChargePotential::potential_energy).
  for (const Potential& potential : potentials_) {
    for (std::size_t i = 0; i < potential.at.size(); ++i) {
      V += charge_load(potential, i, p).potential;
    }
  }
  return S(0.5) * vMv + V;
}

template <typename S>
std::vector<S> FlexibleModelTpl<S>::output_row(S t, const std::vector<S>& y,
                                               const std::vector<double>& impacts) const {
  Scratch& s = scratch_;
  const auto o = static_cast<std::size_t>(rigid_size());
  const auto n = static_cast<std::size_t>(n_);
  std::vector<S> row;
  row.reserve(columns_.size());
  load_modes(y);
  const Pose p = pose(t, y);
  // p_WBo = p_WBr − A p_BoBr; v_WBo = v_WBr − A (ω̄ × p_BoBr).
  const Vector3 p_WBo = p.p_WBr - p.A * p_BoBr_B_;
  const Vector3 v_WBo = p.v_WBr - p.A * p.w_B.cross(p_BoBr_B_);
  row.insert(row.end(),
             {p_WBo(0), p_WBo(1), p_WBo(2), p.theta_WB(0), p.theta_WB(1), p.theta_WB(2),
              p.theta_WB(3), v_WBo(0), v_WBo(1), v_WBo(2), p.w_B(0), p.w_B(1), p.w_B(2)});
  for (const Attachment& a : points_) {
    const Vector3 r = p.p_WBr + attached_offset_W(a, p);
    row.insert(row.end(), {r(0), r(1), r(2)});
  }
  for (std::size_t i = 0; i < n; ++i) row.push_back(y[o + i]);
  for (std::size_t i = 0; i < n; ++i) row.push_back(y[o + n + i]);
  if (prescribed()) {
    // The drive's torque: the rotation rows of M x − rhs at the solved accelerations, to world,
    // along the axis (core::Model::driving_torque), on the right-limit branch at t.
    evaluate(t, static_cast<double>(t), p);
    Vector3 r = s.terms.M_rr.template middleRows<3>(3) * s.x.template head<6>() -
                s.rhs.template segment<3>(3);
    if (formulation_ == core::FlexibleFormulation::kCoupled && n_ > 0) {
      r.noalias() += s.terms.M_rf.template middleRows<3>(3) * s.x.tail(n_);
    }
    row.push_back(axis_W_.dot(p.A * r));
  }
  const S e = energy(t, y);
  row.push_back(e);
  if (dissipates_) {
    const std::size_t integrals = o + 2 * n;
    const S work = y[integrals];
    const S applied = applied_work_ ? y[integrals + 1] : S(0);
    row.push_back(work);
    if (applied_work_) row.push_back(applied);
    row.push_back(e - energy0_ + work - applied);
  }
  if (!wear_channels_.empty()) {
    // Per channel Σ F_n, the slip speed of its most loaded support or pair (the wear_samples of
    // GapSupport and ContactElement), the wear work and the impacts counted by the caller.
    load_modes(y);
    const std::size_t channels = wear_channels_.size();
    std::vector<S> normal(channels, S(0)), largest(channels, S(0)), slip(channels, S(0));
    for (const Support& c : supports_) {
      if (c.channel < 0) continue;
      const auto k = static_cast<std::size_t>(c.channel);
      const SupportLoad load = support_load(c, p);
      if (!(load.normal > S(0))) continue;
      normal[k] += load.normal;
      if (load.normal > largest[k]) {
        largest[k] = load.normal;
        slip[k] = load.slip_speed;
      }
    }
    const std::size_t first_wear = o + 2 * n + (applied_work_ ? 2 : 1);
    for (std::size_t k = 0; k < channels; ++k) {
      row.push_back(normal[k]);
      row.push_back(slip[k]);
      row.push_back(y[first_wear + k]);
      row.push_back(k < impacts.size() ? S(impacts[k]) : S(0));
    }
  }
  return row;
}

template class FlexibleModelTpl<double>;
template class FlexibleModelTpl<long double>;
template class FlexibleModelTpl<boost::multiprecision::float128>;

}  // namespace flexref::precision
