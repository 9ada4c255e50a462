#include "reference/dae_form.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <utility>

#include "rotation/euler_parameters.hpp"

namespace flexref::reference {

namespace {

using ConstMap3 = Eigen::Map<const Eigen::Vector3d>;
using ConstMap4 = Eigen::Map<const Eigen::Vector4d>;
using ConstMapX = Eigen::Map<const Eigen::VectorXd>;
using Map3 = Eigen::Map<Eigen::Vector3d>;
using Map4 = Eigen::Map<Eigen::Vector4d>;
using MapX = Eigen::Map<Eigen::VectorXd>;

}  // namespace

DaeForm::DaeForm(const core::Model& model)
    : model_(&model), fixed_(model.initial_state()), blocks_(body_blocks(model)) {
  for (const Block& k : blocks_) {
    size_ = k.end;
    max_rows_ = std::max(max_rows_, 6 + k.n);
  }
  depth_index_ = size_;
  depth_count_ = model.wear_depth_count();
  size_ += depth_count_;
  if (model.tracks_work()) {
    work_index_ = size_;
    integral_count_ = 1 + model.extra_integral_count();
    size_ += integral_count_;
  }
  if (model.has_constraints()) {
    multiplier_index_ = size_;
    multiplier_count_ = static_cast<int>(model.independent_rows().size());
    active_ = model.independent_rows();
    size_ += 2 * multiplier_count_;
  }
}

std::vector<double> DaeForm::differential_ids() const {
  std::vector<double> ids(static_cast<std::size_t>(size_), 1.0);
  if (multiplier_index_ >= 0) {
    std::fill(ids.begin() + multiplier_index_, ids.end(), 0.0);
    // The works too (out of IDA's error test under IDASetSuppressAlg, still integrated by its
    // BDF): quadratures that nothing in the dynamics reads, one of them the drives' power F_cᵀv,
    // which carries the multipliers' rounding (error_weights.hpp) into its local error estimate
    // and made IDA take 1e-7 s steps on slider_crank at rtol 1e-14. They follow the steps the
    // state's error sets, as SUNDIALS' quadratures without error control (IDASetQuadErrCon).
    if (work_index_ >= 0) {
      std::fill(ids.begin() + work_index_, ids.begin() + work_index_ + integral_count_, 0.0);
    }
  }
  return ids;
}

DaeForm::Scratch DaeForm::make_scratch() const {
  Scratch s;
  s.state = fixed_;
  s.workspace = model_->make_workspace();
  s.accelerations = model_->make_accelerations();
  s.residual = Eigen::VectorXd::Zero(max_rows_);
  s.generalized_rows.reserve(static_cast<std::size_t>(max_rows_));
  for (const core::Body& b : model_->bodies()) {
    const Eigen::Index m = b.is_flexible() ? 6 + b.mode_count() : 0;
    s.body_mass.push_back(Eigen::MatrixXd::Zero(m, m));
  }
  if (model_->has_constraints()) {
    s.velocities = Eigen::VectorXd::Zero(model_->velocity_layout().size());
    s.rows.resize_sparse(model_->constraints()->row_count());  // J by its body blocks
    s.multipliers = Eigen::VectorXd::Zero(2 * model_->velocity_layout().size());
    s.constraint_force = Eigen::VectorXd::Zero(model_->velocity_layout().size());
  }
  return s;
}

void DaeForm::initial_values(const core::LoadContext& context, const core::State& given, double* y,
                             double* yp) const {
  core::Workspace ws = model_->make_workspace();
  core::Accelerations acc = model_->make_accelerations();
  // With joints, the state projected onto Φ = 0, J v + Φ_t = 0 (a restart at an event starts
  // from the solver's state, consistent to its tolerance).
  core::State state = given;
  if (model_->has_constraints()) model_->project(context.t, state, ws);
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
      Map4(y + k.theta) = s.theta_WB;
      Map3(y + k.w) = s.w_WB_B;
      Map4(yp + k.theta) = rotation::euler_parameter_rate(s.theta_WB, s.w_WB_B);
      Map3(yp + k.w) = acc[i].alpha_WB_B;
    }
    MapX(y + k.q, k.n) = s.q_f;
    MapX(y + k.qd, k.n) = s.qd_f;
    MapX(yp + k.q, k.n) = s.qd_f;
    MapX(yp + k.qd, k.n) = acc[i].qdd_f;
  }
  if (depth_count_ > 0) {
    MapX(y + depth_index_, depth_count_) = state.wear_depth;
    model_->wear_depth_rates(
        context, state, ws,
        std::span<double>(yp + depth_index_, static_cast<std::size_t>(depth_count_)));
  }
  if (work_index_ >= 0) {
    for (int j = 0; j < integral_count_; ++j) y[work_index_ + j] = 0.0;
    model_->integral_rates(
        context, state, ws,
        std::span<double>(yp + work_index_, static_cast<std::size_t>(integral_count_)),
        model_->has_constraints() ? &model_->joint_multipliers(ws).force() : nullptr);
  }
  if (multiplier_index_ >= 0) {
    // λ of the constrained accelerations (the same sign: M v̇ = Q − Jᵀ λ) on the DAE's rows (the
    // solve may have chosen others at this state: the same reactions on the DAE's basis), μ = 0;
    // both algebraic.
    const Eigen::VectorXd lambda = model_->joint_multipliers(ws).on_rows(active_);
    for (int j = 0; j < multiplier_count_; ++j) {
      y[multiplier_index_ + j] = lambda(j);
      y[multiplier_index_ + multiplier_count_ + j] = 0.0;
      yp[multiplier_index_ + j] = 0.0;
      yp[multiplier_index_ + multiplier_count_ + j] = 0.0;
    }
  }
}

void DaeForm::unpack(double t, const double* y, core::State& state) const {
  unpack_bodies(*model_, blocks_, fixed_, depth_index_, t, y, state);
}

void DaeForm::mass_rows(const core::LoadContext& context, const double* y,
                        Eigen::Ref<Eigen::MatrixXd> mass, Scratch& scratch) const {
  mass.setIdentity();
  core::State& state = scratch.state;
  core::Accelerations& acc = scratch.accelerations;
  unpack(context.t, y, state);
  std::optional<core::Loads> loads;
  if (model_->has_flexible_bodies())
    loads = model_->compute_wrenches(context, state, scratch.workspace);
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    const core::Body& b = model_->body(static_cast<int>(i));
    // Rows and columns of the body's generalized accelerations (translation, rotation, modes)
    // in y: −1 for the ones the body does not integrate.
    std::vector<int>& at = scratch.generalized_rows;
    at.assign(static_cast<std::size_t>(6 + k.n), -1);
    for (int j = 0; j < 3; ++j) {
      at[static_cast<std::size_t>(j)] = k.v >= 0 ? k.v + j : -1;
      at[static_cast<std::size_t>(3 + j)] = k.w >= 0 ? k.w + j : -1;
    }
    for (int j = 0; j < k.n; ++j) at[static_cast<std::size_t>(6 + j)] = k.qd + j;
    if (b.is_flexible()) {
      // The effective mass matrix the residual multiplies (dynamics_residual fills it).
      auto r = scratch.residual.head(6 + k.n);
      acc[i].a_WBr.setZero();
      acc[i].alpha_WB_B.setZero();
      acc[i].qdd_f.setZero();
      model_->dynamics_residual(static_cast<int>(i), *loads, acc[i], scratch.workspace, r);
      Eigen::MatrixXd& m = scratch.body_mass[i];
      model_->residual_mass_matrix(static_cast<int>(i), scratch.workspace, m);
      for (int row = 0; row < 6 + k.n; ++row) {
        if (at[static_cast<std::size_t>(row)] < 0) continue;
        for (int col = 0; col < 6 + k.n; ++col) {
          if (at[static_cast<std::size_t>(col)] < 0) continue;
          mass(at[static_cast<std::size_t>(row)], at[static_cast<std::size_t>(col)]) = m(row, col);
        }
      }
      continue;
    }
    if (k.v >= 0) mass.block<3, 3>(k.v, k.v) = b.mass() * Eigen::Matrix3d::Identity();
    if (k.w >= 0) mass.block<3, 3>(k.w, k.w) = b.I_Br_B();
  }
}

void DaeForm::residual(const core::LoadContext& context, const double* y, const double* yp,
                       double* res, Scratch& scratch) const {
  // Loads and inertia at the current iterate, with θ̂ = θ/|θ| (A orthogonal, as in the ODE form).
  core::State& state = scratch.state;
  core::Accelerations& acc = scratch.accelerations;
  unpack(context.t, y, state);
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    const core::Body& b = model_->body(static_cast<int>(i));
    if (b.is_prescribed()) {
      // Known rigid accelerations of the law (the rigid rows are the drive's reactions).
      acc[i].a_WBr.setZero();
      const core::RigidBodyDescription& d = b.description();
      acc[i].alpha_WB_B =
          prescribed_attitude(d.prescribed, d.initial.theta_WB, context.t).alpha_WB_B;
    } else {
      acc[i].a_WBr = k.v >= 0 ? Eigen::Vector3d(ConstMap3(yp + k.v)) : Eigen::Vector3d::Zero();
      acc[i].alpha_WB_B = ConstMap3(yp + k.w);  // α̅ = ω̄̇
    }
    acc[i].qdd_f = ConstMapX(yp + k.qd, k.n);
  }
  const core::Loads loads = model_->compute_wrenches(context, state, scratch.workspace);
  const bool joints = multiplier_index_ >= 0;
  const core::VelocityLayout& layout = model_->velocity_layout();
  if (joints) {
    // Jᵀ λ and Jᵀ μ over the independent rows, stacked like the generalized velocities.
    core::ConstraintRows& rows = scratch.rows;
    model_->constraints()->evaluate(context.t, scratch.workspace.kinematics, layout, rows);
    const std::vector<int>& active = active_;
    const auto n_v = static_cast<Eigen::Index>(layout.size());
    auto force = scratch.multipliers.head(n_v);
    auto shift = scratch.multipliers.tail(n_v);
    force.setZero();
    shift.setZero();
    // Each row on its bodies' blocks of J alone (core/constraint_jacobian_tpl.hpp), in column
    // order: the sums are the dense product's term by term, without the O(m N) of the zeros.
    const core::ConstraintJacobian& J = rows.jacobian;
    model_->stack_velocities(state, scratch.velocities);
    for (int j = 0; j < multiplier_count_; ++j) {
      const int r = active[static_cast<std::size_t>(j)];
      std::array<int, 2> slots{0, 1};
      if (J.slot(r, 1).body >= 0 &&
          (J.slot(r, 0).body < 0 || J.slot(r, 1).body < J.slot(r, 0).body))
        std::swap(slots[0], slots[1]);
      const double lambda = y[multiplier_index_ + j];
      const double mu = y[multiplier_index_ + multiplier_count_ + j];
      double jv = 0.0;
      for (const int k : slots) {
        const core::ConstraintJacobian::Slot& slot = J.slot(r, k);
        if (slot.body < 0) continue;
        const auto J_rb = J.values(r, k);
        for (int i = 0; i < slot.width; ++i) {
          const int c = slot.offset + i;
          force(c) += lambda * J_rb(i);
          shift(c) += mu * J_rb(i);
          jv += J_rb(i) * scratch.velocities(c);
        }
      }
      // J v + Φ_t = 0 (λ's equation), Φ = 0 (μ's)
      res[multiplier_index_ + j] = jv + rows.phi_t(r);
      res[multiplier_index_ + multiplier_count_ + j] = rows.phi(r);
    }
  }
  for (std::size_t i = 0; i < state.size(); ++i) {
    const Block& k = blocks_[i];
    auto r = scratch.residual.head(6 + k.n);
    model_->dynamics_residual(static_cast<int>(i), loads, acc[i], scratch.workspace, r);
    const int o = joints ? layout.offset(static_cast<int>(i)) : 0;
    if (joints) r += scratch.multipliers.segment(o, 6 + k.n);  // + Jᵀ λ
    if (k.p >= 0) {
      Map3(res + k.p) = ConstMap3(yp + k.p) - ConstMap3(y + k.v);  // ṗ − v
      Map3(res + k.v) = r.head<3>();                               // m v̇ − f (+ coupling)
      // + Φ_pᵀ μ
      if (joints) Map3(res + k.p) += scratch.multipliers.segment<3>(layout.size() + o);
    }
    if (k.theta >= 0) {
      // θ̇ − ½ θ ⊗ (0, ω̄), with the θ of y (tangent to its sphere) as in the ODE form
      Map4(res + k.theta) =
          ConstMap4(yp + k.theta) -
          rotation::euler_parameter_rate(ConstMap4(y + k.theta), ConstMap3(y + k.w));
      Map3(res + k.w) = r.segment<3>(3);  // I α̅ + ω̄ × I ω̄ − Aᵀ τ (+ coupling)
      if (joints) {
        // + (∂Φ/∂θ)ᵀ μ = 2 Ḡ(θ̂)ᵀ J_ω̄ᵀ μ
        Map4(res + k.theta) += 2.0 * rotation::g_bar_matrix(state[i].theta_WB).transpose() *
                               scratch.multipliers.segment<3>(layout.size() + o + 3);
      }
    }
    MapX(res + k.q, k.n) = ConstMapX(yp + k.q, k.n) - ConstMapX(y + k.qd, k.n);  // q̇ − v_q
    MapX(res + k.qd, k.n) = r.tail(k.n);                                         // modal rows
    if (joints) MapX(res + k.q, k.n) += scratch.multipliers.segment(layout.size() + o + 6, k.n);
  }
  if (depth_count_ > 0) {
    // h' − the contacts' wear rates = 0 (rates into res, then subtracted)
    model_->wear_depth_rates(
        context, state, scratch.workspace,
        std::span<double>(res + depth_index_, static_cast<std::size_t>(depth_count_)));
    for (int j = depth_index_; j < depth_index_ + depth_count_; ++j) res[j] = yp[j] - res[j];
  }
  if (work_index_ >= 0) {
    // W_d' − P = 0, and each extra integral's W' − rate = 0 (rates into res, then subtracted);
    // the drives' power from the DAE's own multipliers, F_c = −Jᵀλ.
    if (joints) scratch.constraint_force = -scratch.multipliers.head(layout.size());
    model_->integral_rates(
        context, state, scratch.workspace,
        std::span<double>(res + work_index_, static_cast<std::size_t>(integral_count_)),
        joints ? &scratch.constraint_force : nullptr);
    for (int j = 0; j < integral_count_; ++j) {
      res[work_index_ + j] = yp[work_index_ + j] - res[work_index_ + j];
    }
  }
}

}  // namespace flexref::reference
