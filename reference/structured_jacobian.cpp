/// \file structured_jacobian.cpp
/// See structured_jacobian.hpp for the construction and its accuracy.
#include "reference/structured_jacobian.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"

namespace flexref::reference {
namespace {

using Kind = StructuredJacobian::TangentColumn::Kind;

std::size_t column_at(int i) { return static_cast<std::size_t>(i); }

/// First unknown generalized-velocity row: free 0, pivot 3 (a = 0), prescribed 6.
int known_rows(const core::Body& b) {
  switch (b.motion()) {
    case core::MotionKind::kFree:
      return 0;
    case core::MotionKind::kPivot:
      return 3;
    case core::MotionKind::kPrescribed:
      return 6;
  }
  return 0;
}

/// The value a tangent column perturbs (for the difference step).
double value_of(const StructuredJacobian::TangentColumn& c, const core::BodyState& s) {
  switch (c.kind) {
    case Kind::kPosition:
      return s.p_WBr(c.index);
    case Kind::kRotation:
      return 0.0;
    case Kind::kVelocity:
      return s.v_WBr(c.index);
    case Kind::kAngularVelocity:
      return s.w_WB_B(c.index);
    case Kind::kMode:
      return s.q_f(c.index);
    case Kind::kModeRate:
      return s.qd_f(c.index);
  }
  return 0.0;
}

}  // namespace

StructuredJacobian::StructuredJacobian(const OdeForm& form) : form_(&form) {
  const core::Model& model = form.model();
  for (int i = 0; i < model.num_bodies(); ++i) {
    const OdeForm::Block& k = form.blocks()[column_at(i)];
    first_column_.push_back(tangent_size_);
    const auto add = [&](Kind kind, int count, int y_offset, bool rotation = false) {
      for (int j = 0; j < count; ++j) {
        columns_.push_back({i, kind, j, rotation ? y_offset : y_offset + j});
      }
      tangent_size_ += count;
    };
    if (k.p >= 0) add(Kind::kPosition, 3, k.p);
    if (k.theta >= 0) add(Kind::kRotation, 3, k.theta, true);
    if (k.v >= 0) add(Kind::kVelocity, 3, k.v);
    if (k.w >= 0) add(Kind::kAngularVelocity, 3, k.w);
    add(Kind::kMode, k.n, k.q);
    add(Kind::kModeRate, k.n, k.qd);
    if (first_column_.back() == tangent_size_) first_column_.back() = -1;
  }
}

StructuredJacobian::Scratch StructuredJacobian::make_scratch() const {
  const core::Model& model = form_->model();
  OdeForm::Scratch base = form_->make_scratch();
  Scratch s;
  s.state = base.state;
  s.perturbed = base.state;
  s.workspace = std::move(base.workspace);
  s.accelerations = std::move(base.accelerations);
  s.work_rows = Eigen::MatrixXd::Zero(form_->integral_count(), tangent_size_);
  s.rates_plus.assign(static_cast<std::size_t>(form_->integral_count()), 0.0);
  s.rates_minus = s.rates_plus;
  for (const core::Body& b : model.bodies()) {
    const int n = b.mode_count();
    BodyScratch bs;
    if (b.is_flexible()) {
      bs.terms = flexible::make_inertia_terms(n);
      bs.solve = flexible::make_mass_solve_scratch(n);
      bs.inertia = flexible::make_inertia_jacobian_scratch(n);
      bs.dR_inertia = Eigen::MatrixXd::Zero(6 + n, 6 + 2 * n);
    }
    bs.dR = Eigen::MatrixXd::Zero(6 + n, tangent_size_);
    bs.x = Eigen::VectorXd::Zero(6 + n);
    bs.load_plus = Eigen::VectorXd::Zero(6 + n);
    bs.load_minus = Eigen::VectorXd::Zero(6 + n);
    bs.column = Eigen::VectorXd::Zero(6 + n);
    bs.dx = Eigen::VectorXd::Zero(6 + n);
    s.bodies.push_back(std::move(bs));
  }
  return s;
}

void StructuredJacobian::perturb(const TangentColumn& c, double h, core::State& state) const {
  core::BodyState& s = state[column_at(c.body)];
  switch (c.kind) {
    case Kind::kPosition:
      s.p_WBr(c.index) += h;
      return;
    case Kind::kRotation:
      // A → A exp(h ẽ_k): θ̂ ⊗ (cos(h/2), sin(h/2) e_k).
      s.theta_WB = rotation::quaternion_multiply(
          s.theta_WB, rotation::exp_quaternion(h * Eigen::Vector3d::Unit(c.index)));
      return;
    case Kind::kVelocity:
      s.v_WBr(c.index) += h;
      return;
    case Kind::kAngularVelocity:
      s.w_WB_B(c.index) += h;
      return;
    case Kind::kMode:
      s.q_f(c.index) += h;
      return;
    case Kind::kModeRate:
      s.qd_f(c.index) += h;
      return;
  }
}

void StructuredJacobian::store_loads(const core::Workspace& ws, bool plus, Scratch& scratch) const {
  for (std::size_t i = 0; i < scratch.bodies.size(); ++i) {
    const core::Wrench& w = ws.wrenches[i];
    Eigen::VectorXd& load = plus ? scratch.bodies[i].load_plus : scratch.bodies[i].load_minus;
    // ℓ = [f_W; Aᵀ τ_Br_W; Q_f], the loads as the residual's rows see them.
    load.head<3>() = w.f_W;
    load.segment<3>(3) = ws.kinematics[i].R_WB.transpose() * w.tau_Br_W;
    load.tail(load.size() - 6) = w.Q_f;
  }
}

void StructuredJacobian::evaluate(const core::LoadContext& context, const double* y,
                                  Eigen::Ref<Eigen::MatrixXd> J, Scratch& s) const {
  evaluate(context, y, J.data(), static_cast<int>(J.outerStride()), s);
}

void StructuredJacobian::evaluate(const core::LoadContext& context, const double* y, double* J_data,
                                  int ld, Scratch& s) const {
  const core::Model& model = form_->model();
  const int N = form_->size();
  Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>> J(J_data, N, N, Eigen::OuterStride<>(ld));
  J.setZero();
  const bool coupled = model.formulation() == core::FlexibleFormulation::kCoupled;

  // The state and its accelerations x, at which R(y, x) is differentiated.
  form_->unpack(context.t, y, s.state);
  model.compute_accelerations(context, s.state, s.workspace, s.accelerations);

  // Inertial part, analytic, and each body's factorization of M_UU.
  for (int i = 0; i < model.num_bodies(); ++i) {
    const core::Body& body = model.body(i);
    const core::BodyState& st = s.state[column_at(i)];
    const core::BodyAcceleration& acc = s.accelerations[column_at(i)];
    BodyScratch& b = s.bodies[column_at(i)];
    b.dR.setZero();
    if (first_column_[column_at(i)] < 0) continue;
    const int n = body.mode_count();
    const int c0 = first_column_[column_at(i)];
    const int c_rot = c0 + (body.is_free() ? 3 : 0);
    const int c_w = c0 + (body.is_free() ? 9 : 3);
    const int c_q = body.is_prescribed() ? c0 : c_w + 3;
    if (!body.is_flexible()) {
      // I α̅ + ω̄ × I ω̄ about Br: ∂/∂ω̄ = −(I ω̄)~ + ω̄̃ I.
      const Eigen::Matrix3d& I = body.I_Br_B();
      b.dR.block<3, 3>(3, c_w) = -rotation::hat(I * st.w_WB_B) + rotation::hat(st.w_WB_B) * I;
      continue;
    }
    const flexible::ModalInvariants& inv = body.invariants();
    const Eigen::Matrix3d R_WB = rotation::rotation_matrix(st.theta_WB);
    if (coupled) {
      flexible::evaluate_inertia_terms(inv, R_WB, st.q_f, st.w_WB_B, st.qd_f, b.terms);
      flexible::factor_coupled(body.modal_mass(), b.terms, known_rows(body), b.solve);
    } else {
      b.column.tail(n).setZero();  // q_f = q̇_f = 0 for the LTE inertia
      flexible::set_undeformed_products(b.terms);
      flexible::assemble_inertia_terms(inv, R_WB, b.column.tail(n), st.w_WB_B, b.column.tail(n),
                                       b.terms);
      flexible::factor_lte(b.terms, known_rows(body), b.solve);
    }
    b.x.head<3>() = acc.a_WBr;
    b.x.segment<3>(3) = acc.alpha_WB_B;
    b.x.tail(n) = acc.qdd_f;
    flexible::inertia_residual_jacobian(inv, b.terms, coupled, st.q_f, st.w_WB_B, st.qd_f, b.x,
                                        body.modal_stiffness(), body.modal_damping(), b.inertia,
                                        b.dR_inertia);
    if (!body.is_prescribed()) {
      b.dR.middleCols<3>(c_rot) = b.dR_inertia.middleCols<3>(flexible::kJacobianRotation);
      b.dR.middleCols<3>(c_w) = b.dR_inertia.middleCols<3>(flexible::kJacobianAngularVelocity);
    }
    b.dR.middleCols(c_q, 2 * n) = b.dR_inertia.middleCols(flexible::kJacobianModes, 2 * n);
  }

  // Loads (and the dissipated power) by central differences, every tangent column:
  // ∂R/∂y −= ∂ℓ/∂y.
  const bool track_work = form_->work_index() >= 0;
  const bool loads = !model.elements().empty();
  if (loads || track_work) {
    const double h_unit = std::cbrt(std::numeric_limits<double>::epsilon());
    for (int c = 0; c < tangent_size_; ++c) {
      const TangentColumn& col = columns_[column_at(c)];
      const double h =
          h_unit * std::max(1.0, std::abs(value_of(col, s.state[column_at(col.body)])));
      for (const double sign : {1.0, -1.0}) {
        s.perturbed = s.state;
        perturb(col, sign * h, s.perturbed);
        if (track_work) {
          model.integral_rates(
              context, s.perturbed, s.workspace,
              sign > 0.0 ? std::span<double>(s.rates_plus) : std::span<double>(s.rates_minus));
        }
        model.compute_wrenches(context, s.perturbed, s.workspace);
        store_loads(s.workspace, sign > 0.0, s);
      }
      for (BodyScratch& b : s.bodies) {
        b.dR.col(c) -= (b.load_plus - b.load_minus) / (2.0 * h);
      }
      for (std::size_t j = 0; j < s.rates_plus.size(); ++j) {
        s.work_rows(static_cast<Eigen::Index>(j), c) =
            (s.rates_plus[j] - s.rates_minus[j]) / (2.0 * h);
      }
    }
  }

  // Acceleration rows: dx = −M_UU⁻¹ ∂R/∂y, per body and tangent column, mapped to y's columns.
  const auto put = [&](int row, const TangentColumn& col, double value) {
    if (col.kind != Kind::kRotation) {
      J(row, col.y_index) += value;
      return;
    }
    // ∂π̄/∂θ = 2 Ḡ(θ̂)/|θ|, row col.index.
    const Eigen::Map<const Eigen::Vector4d> theta(y + col.y_index);
    const rotation::Matrix34d G_bar = rotation::g_bar_matrix(theta / theta.norm());
    for (int m = 0; m < 4; ++m) {
      J(row, col.y_index + m) += value * 2.0 * G_bar(col.index, m) / theta.norm();
    }
  };
  for (int i = 0; i < model.num_bodies(); ++i) {
    const core::Body& body = model.body(i);
    const OdeForm::Block& k = form_->blocks()[column_at(i)];
    BodyScratch& b = s.bodies[column_at(i)];
    const int known = known_rows(body);
    if (known == 6 && !body.is_flexible()) continue;  // a prescribed rigid body: nothing unknown
    const int n = body.mode_count();
    for (int c = 0; c < tangent_size_; ++c) {
      if (b.dR.col(c).isZero(0.0)) continue;
      b.column = -b.dR.col(c);
      if (body.is_flexible()) {
        b.dx.head<6>().setZero();  // the known rows' accelerations do not depend on y
        if (coupled) {
          flexible::apply_coupled(body.modal_mass(), b.terms, b.column, b.solve, b.dx);
        } else {
          flexible::apply_lte(body.modal_mass(), b.terms, b.column, b.solve, b.dx);
        }
      } else {
        b.dx.head<3>() = body.is_free() ? Eigen::Vector3d(b.column.head<3>() / body.mass())
                                        : Eigen::Vector3d::Zero();
        b.dx.segment<3>(3) = body.I_Br_B_inverse() * b.column.segment<3>(3);
      }
      const TangentColumn& col = columns_[column_at(c)];
      if (k.v >= 0) {
        for (int r = 0; r < 3; ++r) put(k.v + r, col, b.dx(r));
      }
      if (k.w >= 0) {
        for (int r = 0; r < 3; ++r) put(k.w + r, col, b.dx(3 + r));
      }
      for (int r = 0; r < n; ++r) put(k.qd + r, col, b.dx(6 + r));
    }
  }
  if (track_work) {
    for (Eigen::Index j = 0; j < s.work_rows.rows(); ++j) {
      for (int c = 0; c < tangent_size_; ++c) {
        put(form_->work_index() + static_cast<int>(j), columns_[column_at(c)], s.work_rows(j, c));
      }
    }
  }

  // Kinematic rows.
  for (int i = 0; i < model.num_bodies(); ++i) {
    const OdeForm::Block& k = form_->blocks()[column_at(i)];
    if (k.p >= 0) {
      for (int r = 0; r < 3; ++r) J(k.p + r, k.v + r) = 1.0;  // ṗ = v
    }
    if (k.theta >= 0) {
      // θ̇ = ½ θ ⊗ (0, ω̄) = ½ [0 −ω̄ᵀ; ω̄ −ω̄̃] θ = ½ Ḡ(θ)ᵀ ω̄, θ as in y.
      const Eigen::Map<const Eigen::Vector4d> theta(y + k.theta);
      const Eigen::Map<const Eigen::Vector3d> w(y + k.w);
      Eigen::Matrix4d d_theta;
      d_theta << 0.0, -w.transpose(), w, -rotation::hat(w);
      J.block<4, 4>(k.theta, k.theta) = 0.5 * d_theta;
      J.block<4, 3>(k.theta, k.w) = 0.5 * rotation::g_bar_matrix(theta).transpose();
    }
    for (int r = 0; r < k.n; ++r) J(k.q + r, k.qd + r) = 1.0;  // q̇_f' = q̇_f
  }
}

}  // namespace flexref::reference
