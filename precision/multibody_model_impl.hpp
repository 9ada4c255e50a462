#pragma once
/// \file multibody_model_impl.hpp
/// MultibodyModelTpl<S>'s definitions, included by the one translation unit per precision that
/// instantiates it (multibody_model_{double,extended,quad}.cpp: three units build in parallel
/// where one took 96 s, docs/performance.md "Build").
#include "precision/multibody_model_tpl.hpp"

// Eigen's NumTraits for float128 before any Eigen type of it.
#include <algorithm>
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

#include "core/attachment_tpl.hpp"
#include "core/body_equations_tpl.hpp"
#include "core/unit_vector_tpl.hpp"
#include "precision/element_conversion.hpp"
#include "reference/exact_rotation_tpl.hpp"
#include "reference/method_choice.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/build_model.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {

template <typename S>
MultibodyModelTpl<S>::MultibodyModelTpl(const scene::SceneSpec& spec,
                                        core::FlexibleFormulation formulation,
                                        double output_spacing)
    : formulation_(formulation) {
  // The double model of the same spec: its outputs (columns, integrals), its discontinuities,
  // and its force elements as it builds them (the laws' parameters, the Hunt–Crossley α from
  // the restitution, the pairs' and supports' points and node rows), in its element order,
  // which numbers the switching functions: every precision solves one model.
  const core::Model built = scene::build_model(spec, formulation);
  int offset = 0;
  for (const scene::BodySpec& body_spec : spec.bodies) {
    const core::RigidBodyDescription& d = body_spec.description;
    Body b;
    b.name = d.name;
    b.motion = d.motion;
    b.prescribed = d.prescribed;
    b.axis_W = core::unit_vector_in<S>(d.prescribed.axis_W);
    const flexible::ModalData* modal = d.flexible ? &d.flexible->modal : nullptr;
    b.n = modal != nullptr ? modal->mode_count() : 0;
    // Invariants about Bo (nodes, then the hub or the rigid body) for the undeformed centre of
    // mass; then about Br (core/body.cpp's construction, every sum and shift in S). A rigid body
    // has no nodes: its invariants are its mass, m c and its second moment.
    const Eigen::VectorXd no_masses;
    const Eigen::Matrix3Xd no_nodes(3, 0);
    const Eigen::MatrixXd no_modes(0, 0);
    const Eigen::VectorXd& masses = modal != nullptr ? modal->mass : no_masses;
    const Eigen::Matrix3Xd& nodes = modal != nullptr ? modal->p_BoNode_B : no_nodes;
    const Eigen::MatrixXd& phi = modal != nullptr ? modal->phi : no_modes;
    const Vector3 hub_c = d.p_BoBcm_B.cast<S>();
    const Eigen::Matrix3d I_sym_d = 0.5 * (d.I_Bcm_B + d.I_Bcm_B.transpose());
    const Matrix3 I_hub = I_sym_d.cast<S>();
    const flexible::GeometricStiffness* geometric =
        modal != nullptr && modal->geometric ? &*modal->geometric : nullptr;
    flexible::ModalInvariantsTpl<S> about_Bo =
        flexible::modal_invariants_tpl<S>(masses, nodes, phi, nullptr);
    flexible::add_rigid_part_tpl<S>(about_Bo, S(d.mass), hub_c, I_hub);
    switch (d.motion) {
      case core::MotionKind::kFree:
        b.p_BoBr_B = about_Bo.s0 / about_Bo.mass;
        break;
      case core::MotionKind::kPivot:
        b.p_BoBr_B = d.p_BoPivot_B.cast<S>();
        break;
      case core::MotionKind::kPrescribed:
        b.p_BoBr_B.setZero();
        break;
    }
    if (modal == nullptr && d.motion == core::MotionKind::kFree) {
      b.p_BoBr_B = hub_c;  // Bcm exactly (s0 / m may differ from it by an ulp)
    }
    b.invariants = flexible::modal_invariants_tpl<S>(masses, nodes, phi, geometric, b.p_BoBr_B);
    flexible::add_rigid_part_tpl<S>(b.invariants, S(d.mass), Vector3(hub_c - b.p_BoBr_B), I_hub);
    if (modal == nullptr) {
      // A rigid body's moments about Br straight from its inertia, J_Br = I_Bcm + m (|c|² 1 −
      // c cᵀ): the route through the second moment (½ tr(I) 1 − I and back) loses the small
      // moments' digits (a slender rod's axial one: ~log10(tr I / I_min) of them).
      const Vector3 c = hub_c - b.p_BoBr_B;
      b.invariants.I0 =
          I_hub + S(d.mass) * (c.squaredNorm() * Matrix3::Identity() - c * c.transpose());
      b.invariants.J0 = (S(0.5) * b.invariants.I0.trace()) * Matrix3::Identity() - b.invariants.I0;
      b.invariants.s0 = S(d.mass) * c;
    }
    b.factor = flexible::ModalMassFactorTpl<S>(b.invariants);
    if (b.n == 0 && b.motion != core::MotionKind::kPrescribed) {
      // The inertia about Br is symmetric positive definite (Body checks it in double, and the
      // scene's values are the same here).
      b.J_Br_inv = b.invariants.I0.inverse();
    }
    b.stiffness = Vector::Zero(b.n);
    b.damping = Vector::Zero(b.n);
    for (int i = 0; i < b.n; ++i) {
      using std::sqrt;
      b.stiffness(i) = S(modal->stiffness(i));
      // d_i = 2 ζ_i √(K_i μ_i), μ_i = (m_ff)_ii (flexible::modal_damping).
      b.damping(i) =
          S(2) * S(modal->damping_ratio(i)) * sqrt(b.stiffness(i) * b.invariants.m_ff(i, i));
    }

    // Initial state (core::Model::initial_state): θ normalized in S; p_WBr = p_WBo + A p_BoBr;
    // v_WBr = v_WBo + A (ω̄ × p_BoBr) (zero for a pivot).
    const core::BodyInitialState& init = d.initial;
    b.theta0 = init.theta_WB.cast<S>();
    {
      using std::sqrt;
      b.theta0 /= sqrt(b.theta0.squaredNorm());
    }
    const Matrix3 A0 = rotation::rotation_matrix_of_any_norm<S>(b.theta0);
    const Vector3 w0 = init.w_WB_B.cast<S>();
    b.p_WBo0 = init.p_WBo.cast<S>();
    if (b.motion != core::MotionKind::kPrescribed) {
      const Vector3 p_WBr = b.p_WBo0 + A0 * b.p_BoBr_B;
      const Vector3 v_WBr = d.motion == core::MotionKind::kPivot
                                ? Vector3::Zero().eval()
                                : Vector3(init.v_WBo.cast<S>() + A0 * w0.cross(b.p_BoBr_B));
      b.initial = {p_WBr(0), p_WBr(1), p_WBr(2), b.theta0(0), b.theta0(1), b.theta0(2), b.theta0(3),
                   v_WBr(0), v_WBr(1), v_WBr(2), w0(0),       w0(1),       w0(2)};
    }
    for (int i = 0; i < b.n; ++i) {
      b.initial.push_back(d.flexible->q0.size() == 0 ? S(0) : S(d.flexible->q0(i)));
    }
    for (int i = 0; i < b.n; ++i) {
      b.initial.push_back(d.flexible->qd0.size() == 0 ? S(0) : S(d.flexible->qd0(i)));
    }
    b.offset = offset;
    offset += static_cast<int>(b.initial.size());
    bodies_.push_back(std::move(b));
  }
  integrals_offset_ = offset;

  const auto attachment = [&](int body, const Eigen::Vector3d& p_BoP_B, int node) {
    Attachment a;
    a.body = body;
    const Body& b = bodies_.at(static_cast<std::size_t>(body));
    a.p_BrP_B = p_BoP_B.cast<S>() - b.p_BoBr_B;
    a.node = node;
    if (node >= 0) {
      const flexible::ModalData& modal =
          spec.bodies[static_cast<std::size_t>(body)].description.flexible->modal;
      a.phi_B = modal.mode_rows(node).template cast<S>();
    }
    return a;
  };
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    for (const core::TrackedPoint& p : spec.bodies[i].description.points) {
      bodies_[i].points.push_back(attachment(static_cast<int>(i), p.p_BoP_B, p.node));
    }
  }
  columns_ = trajectory::trajectory_columns(built);
  dissipates_ = built.dissipates();
  applied_work_ = dissipates_ && built.tracks_applied_work();
  integral_count_ = dissipates_ ? 1 + built.extra_integral_count() : 0;
  discontinuities_ = built.discontinuities();
  for (const Body& b : bodies_) {
    if (b.motion != core::MotionKind::kPrescribed) continue;
    has_prescribed_ = true;
    if (b.prescribed.law.kind == core::AngleLaw::Kind::kSpinUp) {
      discontinuities_.push_back(b.prescribed.law.spin_up_time);
    }
  }
  std::sort(discontinuities_.begin(), discontinuities_.end());
  discontinuities_.erase(std::unique(discontinuities_.begin(), discontinuities_.end()),
                         discontinuities_.end());

  wear_channels_ = built.wear_channel_names();
  // Every element in S, in the double model's order (which numbers the switching functions);
  // each wear channel is one element's (core::Model's wear_elements).
  for (const auto& element : built.elements()) {
    std::unique_ptr<const core::ForceElementTpl<S>> e = element_in<S>(*element);
    if (e == nullptr) {
      // An element of another kind would be left out of this model silently.
      throw std::invalid_argument(spec.name +
                                  ": a force element the extended/quad model does not know; use "
                                  "--precision double");
    }
    int channel = -1;
    if (e->wear_channel_count() > 0) {
      channel = static_cast<int>(
          std::find(wear_channels_.begin(), wear_channels_.end(), e->wear_channel_name()) -
          wear_channels_.begin());
      wear_elements_.resize(wear_channels_.size());
      wear_elements_[static_cast<std::size_t>(channel)] = elements_.size();
    }
    element_channels_.push_back(channel);
    gap_count_ += e->switching_function_count();
    pair_channels_.insert(pair_channels_.end(),
                          static_cast<std::size_t>(e->switching_function_count()), channel);
    elements_.push_back(std::move(e));
  }

  Scratch& s = scratch_;
  s.bodies.resize(bodies_.size());
  s.kinematics.resize(bodies_.size());
  s.wrenches.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const int n = bodies_[i].n;
    BodyScratch& bs = s.bodies[i];
    bs.terms = flexible::make_inertia_terms_tpl<S>(n);
    bs.solve = flexible::make_mass_solve_scratch_tpl<S>(n);
    bs.state.q_f = Vector::Zero(n);
    bs.state.qd_f = Vector::Zero(n);
    bs.zero = Vector::Zero(n);
    bs.rhs = Vector::Zero(6 + n);
    bs.x = Vector::Zero(6 + n);
    s.kinematics[i].p_BoBr_B = bodies_[i].p_BoBr_B;
    s.wrenches[i].Q_f = Vector::Zero(n);
  }
  s.wear_power.assign(wear_channels_.size(), S(0));
  s.wear.assign(wear_channels_.size(), core::WearSampleTpl<S>{});
  s.switching.assign(static_cast<std::size_t>(2 * gap_count_), S(0));
  s.gaps.assign(static_cast<std::size_t>(gap_count_), S(0));
  s.clamps.assign(static_cast<std::size_t>(gap_count_), S(0));

  if (built.has_constraints()) {
    // The double model's joints in S, its independent rows (chosen once, at the initial
    // configuration) and its stabilization rate (reference/method_choice.hpp).
    joints_ = constraints_in<S>(*built.constraints(), built.num_bodies());
    if (joints_ == nullptr) {
      throw std::invalid_argument(spec.name +
                                  ": constraints the extended/quad model does not know; use "
                                  "--precision double");
    }
    layout_ = built.velocity_layout();
    s.constraint =
        core::ConstraintSolveTpl<S>(joints_->row_count(), layout_, built.independent_rows());
    stabilization_ = S(reference::constraint_stabilization_rate(built, output_spacing));
    // The double model's consistent initial state (its Newton projection, in double), refined
    // in S: the scene's data give the state only to double's round-off, and the joints then
    // start violated at ~1e-16 relative, far above extended's and quad's own round-off.
    const core::State consistent = built.initial_state();
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      Body& b = bodies_[i];
      const core::BodyState& x = consistent[i];
      std::size_t k = 0;
      if (b.motion != core::MotionKind::kPrescribed) {
        Quaternion theta = x.theta_WB.cast<S>();
        {
          using std::sqrt;
          theta /= sqrt(theta.squaredNorm());
        }
        const Vector3 p = x.p_WBr.cast<S>();
        const Vector3 v = x.v_WBr.cast<S>();
        const Vector3 w = x.w_WB_B.cast<S>();
        for (int j = 0; j < 3; ++j) b.initial[k++] = p(j);
        for (int j = 0; j < 4; ++j) b.initial[k++] = theta(j);
        for (int j = 0; j < 3; ++j) b.initial[k++] = v(j);
        for (int j = 0; j < 3; ++j) b.initial[k++] = w(j);
      }
      for (int j = 0; j < b.n; ++j) b.initial[k++] = S(x.q_f(j));
      for (int j = 0; j < b.n; ++j) b.initial[k++] = S(x.qd_f(j));
    }
    std::vector<S> y = initial_state();
    load_state(S(0), y);
    joints_->evaluate(S(0), s.kinematics, layout_, s.constraint.rows);
    joint_length_scale_ = core::joint_length_scale<S>(*joints_, layout_, s.constraint.rows.J);
    project(S(0), y);
    for (Body& b : bodies_) {
      const auto first = y.begin() + b.offset;
      std::copy(first, first + static_cast<std::ptrdiff_t>(b.initial.size()), b.initial.begin());
    }
  }
  energy0_ = energy(S(0), initial_state());
}

template <typename S>
void MultibodyModelTpl<S>::apply_inverse_mass(int b, const Eigen::Ref<const Vector>& rhs,
                                              Eigen::Ref<Vector> out) const {
  const Body& body = bodies_[static_cast<std::size_t>(b)];
  BodyScratch& bs = scratch_.bodies[static_cast<std::size_t>(b)];
  if (body.n > 0) {
    // The structured solve of the last evaluate (its known rows take no constraint force). The
    // body's x is free here: apply_constraints has stacked it before the solve.
    bs.x.template head<6>().setZero();
    if (formulation_ == core::FlexibleFormulation::kCoupled) {
      flexible::apply_coupled_tpl<S>(body.factor, bs.terms, rhs, bs.solve, bs.x);
    } else {
      flexible::apply_lte_tpl<S>(body.factor, bs.terms, rhs, bs.solve, bs.x);
    }
    out = bs.x;
    return;
  }
  // Rigid, about Br: M = diag(m 1, J_Br) on (v_WBr, ω̄); a pivot's translation and a prescribed
  // body's motion are fixed.
  out.setZero();
  if (body.motion == core::MotionKind::kPrescribed) return;
  if (body.motion == core::MotionKind::kFree) {
    out.template head<3>() = rhs.template head<3>() / body.invariants.mass;
  }
  out.template segment<3>(3).noalias() = body.J_Br_inv * rhs.template segment<3>(3);
}

template <typename S>
void MultibodyModelTpl<S>::apply_constraints(S t, bool stabilize) const {
  Scratch& s = scratch_;
  core::ConstraintSolveTpl<S>& c = s.constraint;
  joints_->evaluate(t, s.kinematics, layout_, c.rows);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const int o = layout_.offset(static_cast<int>(b));
    const BodyScratch& bs = s.bodies[b];
    const auto width = static_cast<Eigen::Index>(6 + bodies_[b].n);
    c.v.template segment<3>(o) = bs.state.v_WBr;
    c.v.template segment<3>(o + 3) = bs.state.w_WB_B;
    c.v.segment(o + 6, bodies_[b].n) = bs.state.qd_f;
    c.x.segment(o, width) = bs.x.head(width);
  }
  if (stabilize && stabilization_ > S(0)) core::add_baumgarte<S>(stabilization_, c);
  core::solve_constrained_accelerations(
      *joints_, layout_,
      [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out); },
      static_cast<double>(t), c);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const auto width = static_cast<Eigen::Index>(6 + bodies_[b].n);
    s.bodies[b].x.head(width) = c.x.segment(layout_.offset(static_cast<int>(b)), width);
  }
}

template <typename S>
void MultibodyModelTpl<S>::factor_constraints_at(S t, const std::vector<S>& y) const {
  Scratch& s = scratch_;
  load_state(t, y);
  evaluate(t, static_cast<double>(t));  // the flexible bodies' mass factors at the state
  joints_->evaluate(t, s.kinematics, layout_, s.constraint.rows);
  if (!core::factor_constraints(
          *joints_, layout_,
          [&](int b, const auto& rhs, auto&& out) { apply_inverse_mass(b, rhs, out); },
          s.constraint)) {
    core::throw_singular(*joints_, s.constraint, static_cast<double>(t));
  }
}

template <typename S>
S MultibodyModelTpl<S>::relative_position_violation(S t, const std::vector<S>& y) const {
  if (!joints_) return S(0);
  Scratch& s = scratch_;
  load_state(t, y);
  joints_->evaluate(t, s.kinematics, layout_, s.constraint.rows);
  return core::relative_position_violation<S>(*joints_, s.constraint.rows.phi, joint_length_scale_);
}

template <typename S>
S MultibodyModelTpl<S>::project(S t, std::vector<S>& y) const {
  if (!joints_) return S(0);
  Scratch& s = scratch_;
  core::ConstraintSolveTpl<S>& c = s.constraint;
  factor_constraints_at(t, y);
  const S before = core::relative_position_violation<S>(*joints_, c.rows.phi, joint_length_scale_);
  // Converged at a few ε of S: the round-off of Φ, sums of products of lengths of size ℓ
  // (core::Model::project's criterion in double).
  core::project_positions<S>(
      [&] { factor_constraints_at(t, y); },
      [&] {
        return core::relative_position_violation<S>(*joints_, c.rows.phi, joint_length_scale_);
      },
      [&](const Vector& delta) {
        for (std::size_t b = 0; b < bodies_.size(); ++b) {
          const Body& body = bodies_[b];
          const int o = layout_.offset(static_cast<int>(b));
          auto k = static_cast<std::size_t>(body.offset);
          if (body.motion != core::MotionKind::kPrescribed) {
            using std::cos;
            using std::sin;
            using std::sqrt;
            for (std::size_t j = 0; j < 3; ++j) y[k + j] += delta(o + static_cast<Eigen::Index>(j));
            // A ← A exp(δφ̃): θ ← θ ⊗ exp(δφ), renormalized.
            const Vector3 phi = delta.template segment<3>(o + 3);
            const S angle = sqrt(phi.squaredNorm());
            Quaternion e;
            e(0) = cos(S(0.5) * angle);
            e.template tail<3>() =
                angle > S(0) ? Vector3(sin(S(0.5) * angle) / angle * phi) : Vector3(S(0.5) * phi);
            Quaternion theta(y[k + 3], y[k + 4], y[k + 5], y[k + 6]);
            theta = reference::detail::quaternion_multiply<S>(theta, e);
            theta /= sqrt(theta.squaredNorm());
            for (std::size_t j = 0; j < 4; ++j) y[k + 3 + j] = theta(static_cast<Eigen::Index>(j));
            k += 13;
          }
          for (int j = 0; j < body.n; ++j) y[k + static_cast<std::size_t>(j)] += delta(o + 6 + j);
        }
      },
      S(8) * std::numeric_limits<S>::epsilon(), c);
  // The velocities onto J v + Φ_t = 0: linear in v, one correction (c factored at the positions).
  factor_constraints_at(t, y);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const int o = layout_.offset(static_cast<int>(b));
    const BodyScratch& bs = s.bodies[b];
    c.v.template segment<3>(o) = bs.state.v_WBr;
    c.v.template segment<3>(o + 3) = bs.state.w_WB_B;
    c.v.segment(o + 6, bodies_[b].n) = bs.state.qd_f;
  }
  const Vector residual = c.rows.J * c.v + c.rows.phi_t;
  core::constraint_correction<S>(residual, c);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Body& body = bodies_[b];
    const int o = layout_.offset(static_cast<int>(b));
    auto k = static_cast<std::size_t>(body.offset);
    if (body.motion != core::MotionKind::kPrescribed) {
      for (std::size_t j = 0; j < 3; ++j) {
        if (body.motion == core::MotionKind::kFree) {
          y[k + 7 + j] += c.x(o + static_cast<Eigen::Index>(j));
        }
        y[k + 10 + j] += c.x(o + 3 + static_cast<Eigen::Index>(j));
      }
      k += 13;
    }
    const auto n = static_cast<std::size_t>(body.n);
    for (std::size_t j = 0; j < n; ++j) y[k + n + j] += c.x(o + 6 + static_cast<Eigen::Index>(j));
  }
  return before;
}

template <typename S>
std::vector<double> MultibodyModelTpl<S>::discontinuities() const {
  return discontinuities_;
}

template <typename S>
std::vector<S> MultibodyModelTpl<S>::initial_state() const {
  std::vector<S> y;
  y.reserve(static_cast<std::size_t>(state_size()));
  for (const Body& b : bodies_) y.insert(y.end(), b.initial.begin(), b.initial.end());
  y.insert(y.end(), static_cast<std::size_t>(integral_count_), S(0));  // the integrals start at 0
  return y;
}

template <typename S>
void MultibodyModelTpl<S>::load_state(S t, const std::vector<S>& y) const {
  // The loads see the state's q_f under the coupled model, q_f = 0 under LTE (core::Model's
  // pose_bodies).
  const bool lte = formulation_ == core::FlexibleFormulation::kLte;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    BodyScratch& bs = scratch_.bodies[i];
    core::BodyStateTpl<S>& x = bs.state;
    core::BodyKinematicsTpl<S>& k = scratch_.kinematics[i];
    auto o = static_cast<std::size_t>(b.offset);
    bs.alpha_B.setZero();
    if (b.motion == core::MotionKind::kPrescribed) {
      using std::cos;
      using std::sin;
      // θ(t) = q(φ a_W) ⊗ θ0; ω̄ = φ̇ Aᵀ a_W; α̅ = φ̈ Aᵀ a_W (core/prescribed_motion.hpp).
      const S phi = b.prescribed.law.template angle_in<S>(t);
      Quaternion q_axis;
      q_axis << cos(S(0.5) * phi), sin(S(0.5) * phi) * b.axis_W;
      x.theta_WB = reference::detail::quaternion_multiply<S>(q_axis, b.theta0);
      k.R_WB = rotation::rotation_matrix_of_any_norm<S>(x.theta_WB);
      const Vector3 axis_B = k.R_WB.transpose() * b.axis_W;
      x.w_WB_B = b.prescribed.law.template angular_rate_in<S>(t) * axis_B;
      bs.alpha_B = b.prescribed.law.template angular_acceleration_in<S>(t) * axis_B;
      x.p_WBr = b.p_WBo0;  // Br = Bo, fixed on the axis
      x.v_WBr.setZero();
    } else {
      x.p_WBr = Vector3(y[o], y[o + 1], y[o + 2]);
      x.theta_WB = Quaternion(y[o + 3], y[o + 4], y[o + 5], y[o + 6]);
      k.R_WB = rotation::rotation_matrix_of_any_norm<S>(x.theta_WB);
      x.v_WBr = Vector3(y[o + 7], y[o + 8], y[o + 9]);
      x.w_WB_B = Vector3(y[o + 10], y[o + 11], y[o + 12]);
      o += 13;
    }
    const auto n = static_cast<std::size_t>(b.n);
    for (std::size_t j = 0; j < n; ++j) {
      x.q_f(static_cast<Eigen::Index>(j)) = y[o + j];
      x.qd_f(static_cast<Eigen::Index>(j)) = y[o + n + j];
    }
    // A rigid body's loads are Newton–Euler's (its elements apply m g at the centre of mass): no
    // invariants, as core::Model's.
    k.state = &bs.state;
    k.invariants = b.n > 0 ? &b.invariants : nullptr;
    k.q_f = lte ? &bs.zero : &bs.state.q_f;
  }
}

template <typename S>
typename MultibodyModelTpl<S>::Vector3 MultibodyModelTpl<S>::offset_W(const Attachment& a) const {
  // A (x_P − p_BoBr + Φ_k q_f): an attachment always sees the state's deformation
  // (core/node_attachment.hpp), under LTE too.
  const auto i = static_cast<std::size_t>(a.body);
  return core::attached_offset_tpl<S>(scratch_.kinematics[i].R_WB, a.p_BrP_B,
                                      a.node >= 0 ? &a.phi_B : nullptr,
                                      scratch_.bodies[i].state.q_f);
}

template <typename S>
typename MultibodyModelTpl<S>::Vector3 MultibodyModelTpl<S>::position_W(const Attachment& a) const {
  return scratch_.bodies[static_cast<std::size_t>(a.body)].state.p_WBr + offset_W(a);
}

template <typename S>
void MultibodyModelTpl<S>::switching_values(const core::LoadContextTpl<S>& context,
                                            std::vector<S>& values) const {
  Scratch& s = scratch_;
  std::size_t k = 0;
  for (const auto& e : elements_) {
    const auto count = static_cast<std::size_t>(e->switching_function_count());
    if (count == 0) continue;
    e->switching_functions(context, s.kinematics, std::span<S>(s.gaps).subspan(k, count));
    e->clamp_functions(context, s.kinematics, std::span<S>(s.clamps).subspan(k, count));
    k += count;
  }
  interleave_switching(values);
}

template <typename S>
void MultibodyModelTpl<S>::interleave_switching(std::vector<S>& values) const {
  const Scratch& s = scratch_;
  values.resize(2 * s.gaps.size());
  for (std::size_t i = 0; i < s.gaps.size(); ++i) {
    values[2 * i] = s.gaps[i];
    values[2 * i + 1] = s.clamps[i];
  }
}

template <typename S>
void MultibodyModelTpl<S>::sample_wear(const core::LoadContextTpl<S>& context) const {
  Scratch& s = scratch_;
  for (std::size_t c = 0; c < wear_elements_.size(); ++c) {
    elements_[wear_elements_[c]]->wear_samples(context, s.kinematics,
                                               std::span<core::WearSampleTpl<S>>(&s.wear[c], 1));
  }
}

template <typename S>
void MultibodyModelTpl<S>::switching_functions(S t, const std::vector<S>& y,
                                               std::vector<S>& values) const {
  load_state(t, y);
  switching_values(context(t, static_cast<double>(t)), values);
}

template <typename S>
void MultibodyModelTpl<S>::evaluate(S t, double t_segment) const {
  Scratch& s = scratch_;
  // The force elements' loads (core::Model::compute_wrenches), and with them, in one pass over
  // each contact's pairs, the switching values (they come along with every evaluation:
  // switched_integration.hpp) and the integrals' rates (core::Model::integral_rates: every
  // element's dissipation, each wear channel's |F_t·v_t|, and every applied force's power once a
  // harmonic force makes the model track W_a).
  for (core::WrenchTpl<S>& w : s.wrenches) w.set_zero();
  const core::LoadContextTpl<S> ctx = context(t, t_segment);
  s.dissipation = S(0);
  s.applied_power = S(0);
  std::size_t k = 0;
  for (std::size_t j = 0; j < elements_.size(); ++j) {
    const core::ForceElementTpl<S>& e = *elements_[j];
    const auto count = static_cast<std::size_t>(e.switching_function_count());
    const int channel = element_channels_[j];
    std::span<core::WearSampleTpl<S>> wear;
    if (dissipates_ && channel >= 0) wear = {&s.wear[static_cast<std::size_t>(channel)], 1};
    e.add_wrenches_and_rates(ctx, s.kinematics, s.wrenches, dissipates_ ? &s.dissipation : nullptr,
                             wear, std::span<S>(s.gaps).subspan(k, count),
                             std::span<S>(s.clamps).subspan(k, count));
    k += count;
  }
  if (applied_work_) {
    for (const auto& e : elements_) s.applied_power += e->applied_power(ctx, s.kinematics);
  }
  interleave_switching(s.switching);
  if (dissipates_) {
    for (std::size_t c = 0; c < s.wear.size(); ++c) s.wear_power[c] = s.wear[c].wear_power;
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    // Each body's accelerations from its loads (core/body_equations_tpl.hpp, as core::Model):
    // Newton–Euler for a free or pivot rigid body; the structured solve of M v = Qe + Qv −
    // [0; 0; K q + D q̇] otherwise, a prescribed rigid body's too (a body without modes whose
    // rows are all known: its drive torque, output_row, reads the system's rotation rows).
    const Body& b = bodies_[i];
    BodyScratch& bs = s.bodies[i];
    const Matrix3& A = s.kinematics[i].R_WB;
    const core::WrenchTpl<S>& w = s.wrenches[i];
    if (b.n == 0 && b.motion != core::MotionKind::kPrescribed) {
      Vector3 a_WBr;
      Vector3 alpha_WB_B;
      core::rigid_body_accelerations_tpl<S>(b.motion, b.invariants.mass, b.invariants.I0,
                                            b.J_Br_inv, A, w, bs.state.w_WB_B, bs.alpha_B, a_WBr,
                                            alpha_WB_B);
      bs.x.template head<3>() = a_WBr;
      bs.x.template segment<3>(3) = alpha_WB_B;
      continue;
    }
    core::flexible_system_tpl<S>(b.invariants, formulation_, A, bs.state, bs.zero, w, b.stiffness,
                                 b.damping, bs.terms, bs.rhs);
    core::solve_flexible_accelerations_tpl<S>(b.factor, formulation_, bs.terms, b.motion,
                                              bs.alpha_B, bs.rhs, bs.solve, bs.x);
  }
}

template <typename S>
void MultibodyModelTpl<S>::derivative(const std::vector<S>& y, std::vector<S>& dydt, S t,
                                      double t_segment, std::vector<S>* switching) const {
  Scratch& s = scratch_;
  load_state(t, y);
  evaluate(t, t_segment);
  if (joints_) apply_constraints(t, true);
  if (switching != nullptr) *switching = s.switching;
  dydt.resize(y.size());
  S modal_dissipation(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyScratch& bs = s.bodies[i];
    auto o = static_cast<std::size_t>(b.offset);
    if (b.motion != core::MotionKind::kPrescribed) {
      // ṗ = v; θ̇ = ½ θ ⊗ (0, ω̄); v̇ = a; ω̄̇ = α̅.
      const S h(0.5);
      const S e0 = y[o + 3], e1 = y[o + 4], e2 = y[o + 5], e3 = y[o + 6];
      const Vector3& w = bs.state.w_WB_B;
      // A pivot's Br and v_WBr stay (a = 0 is its known row; v starts at 0).
      const bool pivot = b.motion == core::MotionKind::kPivot;
      for (std::size_t k = 0; k < 3; ++k) dydt[o + k] = pivot ? S(0) : y[o + 7 + k];
      dydt[o + 3] = -h * (e1 * w(0) + e2 * w(1) + e3 * w(2));
      dydt[o + 4] = h * (e0 * w(0) + e2 * w(2) - e3 * w(1));
      dydt[o + 5] = h * (e0 * w(1) + e3 * w(0) - e1 * w(2));
      dydt[o + 6] = h * (e0 * w(2) + e1 * w(1) - e2 * w(0));
      for (std::size_t k = 0; k < 3; ++k) {
        dydt[o + 7 + k] = bs.x(static_cast<Eigen::Index>(k));
        dydt[o + 10 + k] = bs.x(static_cast<Eigen::Index>(3 + k));
      }
      o += 13;
    }
    const auto n = static_cast<std::size_t>(b.n);
    for (std::size_t k = 0; k < n; ++k) {
      dydt[o + k] = y[o + n + k];
      dydt[o + n + k] = bs.x(6 + static_cast<Eigen::Index>(k));
    }
    if (n > 0) modal_dissipation += bs.state.qd_f.dot(b.damping.cwiseProduct(bs.state.qd_f));
  }
  if (dissipates_) {
    // Ẇ_d = Σ q̇ᵀ D q̇ + the supports' and bushings' dissipation; Ẇ_a = f·v_P; each wear
    // channel's |F_t·v_t|.
    const auto integrals = static_cast<std::size_t>(integrals_offset_);
    dydt[integrals] = modal_dissipation + s.dissipation;
    for (int k = 1; k < integral_count_; ++k) dydt[integrals + static_cast<std::size_t>(k)] = S(0);
    if (applied_work_) dydt[integrals + 1] = s.applied_power;
    const std::size_t first_wear = integrals + (applied_work_ ? 2 : 1);
    for (std::size_t c = 0; c < s.wear_power.size(); ++c) dydt[first_wear + c] = s.wear_power[c];
  }
}

template <typename S>
S MultibodyModelTpl<S>::energy(S t, const std::vector<S>& y) const {
  Scratch& s = scratch_;
  load_state(t, y);
  S T(0);
  S V(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    BodyScratch& bs = s.bodies[i];
    const Matrix3& A = s.kinematics[i].R_WB;
    const Vector& q = bs.state.q_f;
    const Vector& qd = bs.state.qd_f;
    // T = ½ vᵀ M v, v = (v_WBr, ω̄, q̇_f), M at the state's q_f (core::Model::kinetic_energy,
    // under LTE too): ½ [v_rᵀ M_rr v_r + 2 v_rᵀ M_rf q̇ + q̇ᵀ m_ff q̇].
    flexible::compute_modal_products_tpl<S>(b.invariants, q, bs.zero, bs.terms);
    flexible::assemble_inertia_terms_tpl<S>(b.invariants, A, q, bs.state.w_WB_B, bs.zero, bs.terms);
    Eigen::Matrix<S, 6, 1> v_r;
    v_r << bs.state.v_WBr, bs.state.w_WB_B;
    T += S(0.5) * (v_r.dot(bs.terms.M_rr * v_r) + S(2) * v_r.dot(bs.terms.M_rf * qd) +
                   qd.dot(b.invariants.m_ff * qd));
    // V = ½ q_fᵀ K q_f + the elements' potentials below.
    V += S(0.5) * q.dot(b.stiffness.cwiseProduct(q));
  }
  // The elements' potentials: gravity on the loads' q_f (zero under LTE), the bushings' springs,
  // the point charges', the contacts' and gap supports' V_law(δ) at the deformed points.
  const core::LoadContextTpl<S> ctx = context(t, static_cast<double>(t));
  for (const auto& e : elements_) V += e->potential_energy(ctx, s.kinematics);
  return T + V;
}

template <typename S>
std::vector<S> MultibodyModelTpl<S>::output_row(S t, const std::vector<S>& y,
                                                const std::vector<double>& impacts) const {
  Scratch& s = scratch_;
  std::vector<S> row;
  row.reserve(columns_.size());
  load_state(t, y);
  // The drives' torques and the joints' reactions need the accelerations at (t, y), on the
  // right-limit branch at t; the reactions from the plain index-1 form (no stabilization terms:
  // core::Model::joint_reactions').
  if (has_prescribed_ || joints_) evaluate(t, static_cast<double>(t));
  if (joints_) apply_constraints(t, false);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const BodyScratch& bs = s.bodies[i];
    const core::BodyStateTpl<S>& p = bs.state;
    const Matrix3& A = s.kinematics[i].R_WB;
    // p_WBo = p_WBr − A p_BoBr; v_WBo = v_WBr − A (ω̄ × p_BoBr).
    const Vector3 p_WBo = p.p_WBr - A * b.p_BoBr_B;
    const Vector3 v_WBo = p.v_WBr - A * p.w_WB_B.cross(b.p_BoBr_B);
    row.insert(row.end(), {p_WBo(0), p_WBo(1), p_WBo(2), p.theta_WB(0), p.theta_WB(1),
                           p.theta_WB(2), p.theta_WB(3), v_WBo(0), v_WBo(1), v_WBo(2), p.w_WB_B(0),
                           p.w_WB_B(1), p.w_WB_B(2)});
    for (const Attachment& a : b.points) {
      const Vector3 r = position_W(a);
      row.insert(row.end(), {r(0), r(1), r(2)});
    }
    for (Eigen::Index k = 0; k < b.n; ++k) row.push_back(p.q_f(k));
    for (Eigen::Index k = 0; k < b.n; ++k) row.push_back(p.qd_f(k));
    if (b.motion == core::MotionKind::kPrescribed) {
      // The drive's torque: the rotation rows of M x − rhs at the solved accelerations, to
      // world, along the axis (core::Model::driving_torque).
      Vector3 r = bs.terms.M_rr.template middleRows<3>(3) * bs.x.template head<6>() -
                  bs.rhs.template segment<3>(3);
      if (formulation_ == core::FlexibleFormulation::kCoupled && b.n > 0) {
        r.noalias() += bs.terms.M_rf.template middleRows<3>(3) * bs.x.tail(b.n);
      }
      row.push_back(b.axis_W.dot(A * r));
    }
  }
  if (joints_) {
    // Per joint: its reaction on its first body (force, torque about the joint point; world)
    // from the minimum-norm multipliers, and its largest position and velocity violation
    // (trajectory::tabulate's columns).
    const std::vector<core::JointReactionTpl<S>> reactions =
        core::joint_reactions_from_solve<S>(*joints_, s.kinematics, layout_, s.constraint);
    const std::vector<std::array<S, 2>> violations =
        core::joint_violations<S>(*joints_, s.constraint.rows, s.constraint.v);
    for (std::size_t j = 0; j < reactions.size(); ++j) {
      const core::JointReactionTpl<S>& r = reactions[j];
      row.insert(row.end(), {r.f_W(0), r.f_W(1), r.f_W(2), r.tau_W(0), r.tau_W(1), r.tau_W(2),
                             violations[j][0], violations[j][1]});
    }
  }
  const S e = energy(t, y);
  row.push_back(e);
  const auto integrals = static_cast<std::size_t>(integrals_offset_);
  if (dissipates_) {
    const S work = y[integrals];
    const S applied = applied_work_ ? y[integrals + 1] : S(0);
    row.push_back(work);
    if (applied_work_) row.push_back(applied);
    row.push_back(e - energy0_ + work - applied);  // E(t) − E(0) + W_d(t) − W_a(t)
  }
  if (!wear_channels_.empty()) {
    // Per channel Σ F_n, the slip speed of its most loaded support or pair (the element's
    // wear_samples), the wear work and the impacts counted by the caller.
    sample_wear(context(t, static_cast<double>(t)));
    const std::size_t first_wear = integrals + (applied_work_ ? 2 : 1);
    for (std::size_t k = 0; k < wear_channels_.size(); ++k) {
      row.push_back(s.wear[k].normal_force);
      row.push_back(s.wear[k].slip_speed);
      row.push_back(y[first_wear + k]);
      row.push_back(k < impacts.size() ? S(impacts[k]) : S(0));
    }
  }
  return row;
}

}  // namespace flexref::precision
