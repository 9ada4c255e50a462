#include "lie/genalpha_newton.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/body_coupling.hpp"
#include "core/prescribed_motion.hpp"
#include "lie/scheme_support.hpp"
#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"

namespace flexref::lie::detail {

using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

/// Forward-difference step of the loads' directional derivatives (see the header).
constexpr double kDirectionalStep = 1.5e-8;

/// Row `row` of J on body `body`'s columns: that body's block (core/constraint_jacobian_tpl.hpp;
/// J is stored by its blocks only, the rest is zero).
core::ConstraintJacobian::ConstBlock row_block(const core::ConstraintJacobian& J, int row,
                                               int body) {
  return J.values(row, J.slot(row, 0).body == body ? 0 : 1);
}

}  // namespace

GenAlphaSystem::GenAlphaSystem(const core::Model& model, const GenAlphaParameters& parameters)
    : model_(model),
      p_(parameters),
      n_bodies_(model.num_bodies()),
      layout_(model.velocity_layout()),
      next_(model.initial_state()),
      perturbed_(next_),
      ws_(model.make_workspace()),
      wrenches_(ws_.wrenches),
      R_(static_cast<std::size_t>(model.num_bodies()), Matrix3d::Identity()),
      acc_(model.make_accelerations()) {
  coupling_ = core::body_coupling(model);
  const std::vector<int> colour = core::colour_bodies(coupling_);
  for (int b = 0; b < n_bodies_; ++b) {
    const auto c = static_cast<std::size_t>(colour[static_cast<std::size_t>(b)]);
    if (c >= colours_.size()) colours_.resize(c + 1);
    colours_[c].push_back(b);
  }
  source_.assign(static_cast<std::size_t>(n_bodies_), -1);
  for (const std::vector<int>& bodies : colours_) {
    for (Eigen::Index k = 0;; ++k) {
      bool any = false, inside = false;
      for (const int j : bodies) {
        inside = inside || k < layout_.width(j);
        any = any || moves(j, k);
      }
      if (!inside) break;
      matrix_evaluations_ += any ? 1 : 0;
    }
  }
  for (int b = 0; b < n_bodies_; ++b) {
    const core::Body& body = model.body(b);
    const int width = layout_.width(b);
    body_residual_.push_back(Eigen::VectorXd::Zero(width));
    body_residual_base_.push_back(Eigen::VectorXd::Zero(width));
    mass_.push_back(body.is_flexible() ? Eigen::MatrixXd::Zero(width, width) : Eigen::MatrixXd());
  }
  const Eigen::Index n = layout_.size();
  if (model.has_constraints()) {
    n_multipliers_ = static_cast<int>(model.independent_rows().size());
    active_ = model.independent_rows();
    const int rows = model.constraints()->row_count();
    rows_.resize_sparse(rows);  // J by its body blocks
    rows_perturbed_.resize_sparse(rows);
    // The rows' block pattern now, not at the first evaluation (steps allocate nothing).
    model.constraints()->prepare_rows(model.velocity_layout(), rows_);
    model.constraints()->prepare_rows(model.velocity_layout(), rows_perturbed_);
  }
  z_size_ = n + n_multipliers_;
  v_n_ = Eigen::VectorXd::Zero(n);
  a_n_ = Eigen::VectorXd::Zero(n);
  vdot_n_ = Eigen::VectorXd::Zero(n);
  a_base_ = Eigen::VectorXd::Zero(n);
  vdot_ = Eigen::VectorXd::Zero(n);
  a_ = Eigen::VectorXd::Zero(n);
  v_ = Eigen::VectorXd::Zero(n);
  diagonal_ = Eigen::VectorXd::Zero(n);
  jt_lambda_ = Eigen::VectorXd::Zero(n);
  jt_lambda_terms_ = Eigen::VectorXd::Zero(n);
  jt_lambda_perturbed_ = Eigen::VectorXd::Zero(n);
  // m̂ = β h² M_kk β' = M_kk (1 − α_m)/(1 − α_f): independent of h (modal rows: the diagonal of
  // the modal mass m_ff).
  const double ratio = (1.0 - p_.alpha_m) / (1.0 - p_.alpha_f);
  for (int b = 0; b < n_bodies_; ++b) {
    const core::Body& body = model.body(b);
    const auto o = static_cast<Eigen::Index>(offset(b));
    diagonal_.segment<3>(o).setConstant(ratio * body.mass());
    diagonal_.segment<3>(o + 3) = ratio * body.I_Br_B().diagonal();
    if (body.is_flexible()) {
      diagonal_.segment(o + 6, body.mode_count()) = ratio * body.invariants().m_ff.diagonal();
    }
    // A fixed row needs a non-zero diagonal (a prescribed beam's hub may have no inertia about
    // an axis): the body's mass stands in.
    for (int k = 0; k < 6; ++k) {
      if (!(diagonal_(o + k) > 0.0)) diagonal_(o + k) = ratio * std::max(body.mass(), 1.0);
    }
  }
}

void GenAlphaSystem::begin_step(double t_n, double h, const core::State& state,
                                const Eigen::VectorXd& vdot_n, const Eigen::VectorXd& a_n) {
  t_n_ = t_n;
  h_ = h;
  state_n_ = &state;
  stack_velocities(state, v_n_);
  vdot_n_ = vdot_n;
  a_n_ = a_n;
  // a_{n+1} = x/(β h²) + a_base,  a_base = −(v_n + (½ − β) h a_n)/(β h)
  a_base_ = -(v_n_ + ((0.5 - p_.beta) * h) * a_n_) / (p_.beta * h);
}

void GenAlphaSystem::predictor(const Eigen::VectorXd& lambda_hat, Eigen::VectorXd& z) const {
  const Eigen::Index n = layout_.size();
  // v̇_{n+1} = 0 (Brüls, Cardona & Arnold's predictor: bounded however stiff the problem, where
  // extrapolating v̇_n by h ω ≫ 1 would start Newton far off, at another root of a nonlinear
  // spring): a_{n+1} = (α_f v̇_n − α_m a_n)/(1 − α_m),  x = β h² (a_{n+1} − a_base)
  const double bh2 = p_.beta * h_ * h_;
  for (int b = 0; b < n_bodies_; ++b) {
    for (int k = offset(b); k < offset(b + 1); ++k) {
      if (!integrated_row(b, k - offset(b))) {
        z(k) = 0.0;
        continue;
      }
      const double a_next = (p_.alpha_f * vdot_n_(k) - p_.alpha_m * a_n_(k)) / (1.0 - p_.alpha_m);
      z(k) = bh2 * (a_next - a_base_(k));
    }
  }
  if (n_multipliers_ > 0) z.tail(n_multipliers_) = lambda_hat;
  (void)n;
}

void GenAlphaSystem::state_at(const Eigen::VectorXd& z, core::State& next, Eigen::VectorXd& vdot,
                              Eigen::VectorXd& a) const {
  const core::State& s_n = *state_n_;
  const double bh2 = p_.beta * h_ * h_;
  const Eigen::Index n = layout_.size();
  // a_{n+1} = x/(β h²) + a_base
  a = z.head(n) / bh2 + a_base_;
  // v̇_{n+1} = ((1 − α_m) a_{n+1} + α_m a_n − α_f v̇_n)/(1 − α_f)
  vdot = ((1.0 - p_.alpha_m) * a + p_.alpha_m * a_n_ - p_.alpha_f * vdot_n_) / (1.0 - p_.alpha_f);
  const double c_n = (1.0 - p_.gamma) * h_;
  const double c_np1 = p_.gamma * h_;
  for (int b = 0; b < n_bodies_; ++b) {
    const core::BodyState& s = s_n[static_cast<std::size_t>(b)];
    core::BodyState& s1 = next[static_cast<std::size_t>(b)];
    const auto o = static_cast<Eigen::Index>(offset(b));
    if (model_.body(b).is_free()) {
      // x_{n+1} = x_n + x_T,  v_{n+1} = v_n + (1 − γ) h a_n + γ h a_{n+1}
      s1.p_WBr = s.p_WBr + z.segment<3>(o);
      s1.v_WBr = s.v_WBr + c_n * a_n_.segment<3>(o) + c_np1 * a.segment<3>(o);
    } else {
      s1.p_WBr = s.p_WBr;
      s1.v_WBr.setZero();
      a.segment<3>(o).setZero();
      vdot.segment<3>(o).setZero();
    }
    // R_{n+1} = R_n exp(x̃_R)   (θ_{n+1} = θ_n ⊗ exp(x_R), renormalized)
    s1.theta_WB =
        rotation::quaternion_multiply(s.theta_WB, rotation::exp_quaternion(z.segment<3>(o + 3)));
    renormalize_unit_product(s1.theta_WB);
    s1.w_WB_B = s.w_WB_B + c_n * a_n_.segment<3>(o + 3) + c_np1 * a.segment<3>(o + 3);
    const Eigen::Index modes = s.q_f.size();
    if (modes > 0) {
      // q_{n+1} = q_n + x_q (a vector space),  q̇_{n+1} = q̇_n + (1 − γ) h q̈ₐ_n + γ h q̈ₐ_{n+1}
      s1.q_f = s.q_f + z.segment(o + 6, modes);
      s1.qd_f = s.qd_f + c_n * a_n_.segment(o + 6, modes) + c_np1 * a.segment(o + 6, modes);
    }
  }
  model_.apply_prescribed_motion(t_n_ + h_, next);
}

void GenAlphaSystem::body_residual(int b, const core::Loads& loads) {
  const core::Body& body = model_.body(b);
  core::BodyAcceleration& acc = acc_[static_cast<std::size_t>(b)];
  const auto o = static_cast<Eigen::Index>(offset(b));
  acc.a_WBr = vdot_.segment<3>(o);
  acc.alpha_WB_B = vdot_.segment<3>(o + 3);
  if (body.is_prescribed()) {
    const core::RigidBodyDescription& d = body.description();
    acc.a_WBr.setZero();
    acc.alpha_WB_B =
        core::prescribed_attitude(d.prescribed, d.initial.theta_WB, t_n_ + h_).alpha_WB_B;
  } else if (!body.is_free()) {
    acc.a_WBr.setZero();
  }
  if (body.mode_count() > 0) acc.qdd_f = vdot_.segment(o + 6, body.mode_count());
  model_.dynamics_residual(b, loads, acc, ws_, body_residual_[static_cast<std::size_t>(b)]);
}

GenAlphaResidualNorm GenAlphaSystem::residual(const Eigen::VectorXd& z, Eigen::VectorXd& r) {
  state_at(z, next_, vdot_, a_);
  stack_velocities(next_, v_);
  const double t_np1 = t_n_ + h_;
  const core::Loads loads =
      model_.compute_wrenches(core::LoadContext{t_np1, t_n_ + 0.5 * h_}, next_, ws_);
  ++evaluations_;
  for (int b = 0; b < n_bodies_; ++b) {
    const auto k = static_cast<std::size_t>(b);
    wrenches_[k].f_W = ws_.wrenches[k].f_W;
    wrenches_[k].tau_Br_W = ws_.wrenches[k].tau_Br_W;
    wrenches_[k].torque_magnitude = ws_.wrenches[k].torque_magnitude;
    R_[k] = ws_.kinematics[k].R_WB;
  }
  const Eigen::Index n = layout_.size();
  jt_lambda_.setZero();
  jt_lambda_terms_.setZero();
  if (n_multipliers_ > 0) {
    model_.constraints()->evaluate(t_np1, ws_.kinematics, model_.velocity_layout(), rows_);
    // J_aᵀ λ̂ (λ̂ = β h² λ), each row on its two bodies' blocks
    add_rows_transpose(rows_, z, jt_lambda_, &jt_lambda_terms_);
  }
  const double bh2 = p_.beta * h_ * h_;
  GenAlphaResidualNorm norm;
  const auto note = [&](double value, double scale, int body) {
    const double relative = std::abs(value) / (scale > 0.0 ? scale : 1.0);
    if (!std::isfinite(relative)) norm.finite = false;
    if (relative > norm.relative) {
      norm.relative = relative;
      norm.worst_body = body;
    }
  };
  for (int b = 0; b < n_bodies_; ++b) {
    const core::Body& body = model_.body(b);
    const auto o = static_cast<Eigen::Index>(offset(b));
    const core::Wrench& w = wrenches_[static_cast<std::size_t>(b)];
    // Scales: the terms of each row, and the inertia of the increment itself, m̂ |x| (without
    // it a row whose terms all vanish — a free body without loads — would be measured against
    // its own round-off).
    const Vector3d inertia_x_T = diagonal_.segment<3>(o).cwiseProduct(z.segment<3>(o));
    const Vector3d inertia_x_R = diagonal_.segment<3>(o + 3).cwiseProduct(z.segment<3>(o + 3));
    if (body.is_flexible()) {
      // r_b = β h² (M v̇ − Q) + (Jᵀ λ̂)_b, Model::dynamics_residual's rows.
      const auto k = static_cast<std::size_t>(b);
      body_residual(b, loads);
      model_.residual_mass_matrix(b, ws_, mass_[k]);
      const Eigen::Index width = offset(b + 1) - offset(b);
      r.segment(o, width) = bh2 * body_residual_[k] + jt_lambda_.segment(o, width);
      // One scale for the whole body, the largest of its rows' terms: a modal row's own terms can
      // be 1e-8 of the hub's while the coupled solve leaves it the round-off of the hub's rows.
      double body_scale = 0.0;
      for (Eigen::Index i = 0; i < width; ++i) {
        if (!integrated_row(b, static_cast<int>(i))) continue;
        const double inertia = mass_[k].row(i).dot(vdot_.segment(o, width));
        const double inertia_terms =
            mass_[k].row(i).cwiseAbs().dot(vdot_.segment(o, width).cwiseAbs());
        // The loads' and the body's own forces: Qe (f, Rᵀτ, Q_f), Qv, K q and D q̇.
        double forces =
            std::abs(ws_.flexible[k].terms.Qv(i)) + std::abs(body_residual_[k](i) - inertia);
        if (i < 3) forces += std::abs(w.f_W(i));
        if (i >= 3 && i < 6) {
          forces += std::abs((R_[k].transpose() * w.tau_Br_W)(i - 3)) + w.torque_magnitude;
        }
        if (i >= 6) {
          const Eigen::Index m = i - 6;
          const core::BodyState& s1 = next_[k];
          forces += std::abs(w.Q_f(m)) + std::abs(body.modal_stiffness()(m) * s1.q_f(m)) +
                    std::abs(body.modal_damping()(m) * s1.qd_f(m));
        }
        body_scale = std::max(body_scale, bh2 * (inertia_terms + forces) + jt_lambda_terms_(o + i) +
                                              std::abs(diagonal_(o + i) * z(o + i)));
      }
      for (Eigen::Index i = 0; i < width; ++i) {
        if (!integrated_row(b, static_cast<int>(i))) {
          r(o + i) = diagonal_(o + i) * z(o + i);  // keeps x_k = 0
          continue;
        }
        note(r(o + i), body_scale, b);
      }
      continue;
    }
    const Matrix3d& J = body.I_Br_B();
    const Vector3d W = v_.segment<3>(o + 3);
    const Vector3d J_W = J * W;
    const Vector3d gyroscopic = W.cross(J_W);
    const Vector3d torque_B = R_[static_cast<std::size_t>(b)].transpose() * w.tau_Br_W;
    const Vector3d inertia_T = body.mass() * vdot_.segment<3>(o);
    const Vector3d inertia_R = J * vdot_.segment<3>(o + 3);
    // r_T = β h² (m v̇_T − f_W) + (Jᵀ λ̂)_T,  r_R = β h² (J v̇_R + W × J W − Rᵀ τ_W) + (Jᵀ λ̂)_R
    r.segment<3>(o) = bh2 * (inertia_T - w.f_W) + jt_lambda_.segment<3>(o);
    r.segment<3>(o + 3) = bh2 * (inertia_R + gyroscopic - torque_B) + jt_lambda_.segment<3>(o + 3);
    const double scale_T = bh2 * (max_abs(inertia_T) + max_abs(w.f_W)) +
                           max_abs(jt_lambda_terms_.segment<3>(o)) + max_abs(inertia_x_T);
    const double scale_R =
        bh2 * (max_abs(inertia_R) + max_abs(gyroscopic) + max_abs(torque_B) + w.torque_magnitude) +
        max_abs(jt_lambda_terms_.segment<3>(o + 3)) + max_abs(inertia_x_R);
    for (int k = 0; k < 6; ++k) {
      if (!integrated_row(b, k)) {
        r(o + k) = diagonal_(o + k) * z(o + k);  // keeps x_k = 0
        continue;
      }
      note(r(o + k), k < 3 ? scale_T : scale_R, b);
    }
  }
  if (n_multipliers_ > 0) {
    // Length rows relative to the size of the bodies' positions (at least 1 cm), rotation rows
    // (sines of angles) as they are.
    double length = 1e-2;
    for (const core::BodyState& s : next_) length = std::max(length, max_abs(s.p_WBr));
    const std::vector<int>& active = active_;
    for (int a = 0; a < n_multipliers_; ++a) {
      const int row = active[static_cast<std::size_t>(a)];
      r(n + a) = rows_.phi(row);
      const double scale = model_.constraints()->is_length_row(row) ? length : 1.0;
      note(r(n + a), scale, std::max(0, model_.constraints()->row_bodies(row)[0]));
    }
  }
  if (!std::isfinite(r.sum())) norm.finite = false;
  return norm;
}

void GenAlphaSystem::add_rows_transpose(const core::ConstraintRows& rows, const Eigen::VectorXd& z,
                                        Eigen::VectorXd& out, Eigen::VectorXd* terms) const {
  const Eigen::Index n = layout_.size();
  for (int a = 0; a < n_multipliers_; ++a) {
    const int row = active_[static_cast<std::size_t>(a)];
    const std::array<int, 2> ends = model_.constraints()->row_bodies(row);
    for (const int b : ends) {
      if (b < 0 || (b == ends[1] && ends[0] == ends[1])) continue;  // one body's block once
      const auto o = static_cast<Eigen::Index>(offset(b));
      const Eigen::Index width = offset(b + 1) - offset(b);
      const auto J_b = row_block(rows.jacobian, row, b);
      out.segment(o, width) += J_b * z(n + a);
      if (terms != nullptr) terms->segment(o, width) += J_b.cwiseAbs() * std::abs(z(n + a));
    }
  }
}

void GenAlphaSystem::make_iteration_matrix(Eigen::SparseMatrix<double>& S) const {
  const Eigen::Index n = layout_.size();
  std::vector<Eigen::Triplet<double>> entries;
  const auto block = [&](Eigen::Index r0, Eigen::Index rows, Eigen::Index c0, Eigen::Index cols) {
    for (Eigen::Index c = c0; c < c0 + cols; ++c) {
      for (Eigen::Index r = r0; r < r0 + rows; ++r) entries.emplace_back(r, c, 0.0);
    }
  };
  for (int i = 0; i < n_bodies_; ++i) {
    for (const int k : coupling_[static_cast<std::size_t>(i)]) {
      block(offset(i), offset(i + 1) - offset(i), offset(k), offset(k + 1) - offset(k));
    }
  }
  for (int a = 0; a < n_multipliers_; ++a) {
    for (const int b : model_.constraints()->row_bodies(active_[static_cast<std::size_t>(a)])) {
      if (b < 0) continue;
      block(offset(b), offset(b + 1) - offset(b), n + a, 1);
      block(n + a, 1, offset(b), offset(b + 1) - offset(b));
    }
  }
  for (Eigen::Index k = 0; k < z_size_; ++k) entries.emplace_back(k, k, 0.0);
  S.resize(z_size_, z_size_);
  S.setFromTriplets(entries.begin(), entries.end());
  S.makeCompressed();
}

void GenAlphaSystem::iteration_matrix(const Eigen::VectorXd& z, Eigen::MatrixXd& S) {
  Eigen::SparseMatrix<double> sparse;
  make_iteration_matrix(sparse);
  iteration_matrix(z, sparse);
  S = Eigen::MatrixXd(sparse);
}

void GenAlphaSystem::iteration_matrix(const Eigen::VectorXd& z, Eigen::SparseMatrix<double>& S) {
  const double bh2 = p_.beta * h_ * h_;
  const double gamma_prime = p_.gamma / (p_.beta * h_);                // ∂v_{n+1}/∂x
  const double mass_factor = (1.0 - p_.alpha_m) / (1.0 - p_.alpha_f);  // β h² β'
  const Eigen::Index n = layout_.size();
  S.coeffs().setZero();
  // Inertia, gyroscopic damping, the frame of the torque (analytic); fixed rows m̂ I.
  for (int b = 0; b < n_bodies_; ++b) {
    const core::Body& body = model_.body(b);
    const auto o = static_cast<Eigen::Index>(offset(b));
    const Eigen::Index width = offset(b + 1) - offset(b);
    for (Eigen::Index k = 0; k < width; ++k) S.coeffRef(o + k, o + k) = diagonal_(o + k);
    if (body.is_flexible()) {
      // β h² M β' from the residual's mass matrix, on the integrated rows and columns.
      const Eigen::MatrixXd& M = mass_[static_cast<std::size_t>(b)];
      for (Eigen::Index i = 0; i < width; ++i) {
        if (!integrated_row(b, static_cast<int>(i))) continue;
        for (Eigen::Index j = 0; j < width; ++j) {
          if (integrated_row(b, static_cast<int>(j)))
            S.coeffRef(o + i, o + j) = mass_factor * M(i, j);
        }
      }
      body_residual_base_[static_cast<std::size_t>(b)] =
          body_residual_[static_cast<std::size_t>(b)];
      continue;
    }
    if (body.is_prescribed()) continue;
    const Matrix3d& J = body.I_Br_B();
    const Vector3d W = v_.segment<3>(o + 3);
    const Vector3d torque_B = R_[static_cast<std::size_t>(b)].transpose() *
                              wrenches_[static_cast<std::size_t>(b)].tau_Br_W;
    const Matrix3d T = rotation::right_jacobian(z.segment<3>(o + 3));
    // β h² (J β' + (W̃ J − (J W)~) γ' − (Rᵀτ)~ T);  β h² J β' = J (1 − α_m)/(1 − α_f)
    const Matrix3d rotation_block =
        J * mass_factor + bh2 * (gamma_prime * (rotation::hat(W) * J - rotation::hat(J * W)) -
                                 rotation::hat(torque_B) * T);
    for (Eigen::Index c = 0; c < 3; ++c) {
      for (Eigen::Index r = 0; r < 3; ++r) S.coeffRef(o + 3 + r, o + 3 + c) = rotation_block(r, c);
    }
  }
  // The loads' K T + C γ' (a flexible body: its whole residual at fixed v̇; and the joints'
  // ∂(Jᵀλ̂)/∂x): one directional forward difference per colour of bodies and unknown, the
  // unknown moved in every body of the colour at once (colours_: each body's equations see one
  // of them at most, source_).
  const core::LoadContext context{t_n_ + h_, t_n_ + 0.5 * h_};
  const double eps = kDirectionalStep;
  for (const std::vector<int>& bodies : colours_) {
    std::fill(source_.begin(), source_.end(), -1);
    Eigen::Index widest = 0;
    for (const int j : bodies) {
      for (const int i : coupling_[static_cast<std::size_t>(j)])
        source_[static_cast<std::size_t>(i)] = j;
      widest = std::max<Eigen::Index>(widest, offset(j + 1) - offset(j));
    }
    for (Eigen::Index k = 0; k < widest; ++k) {
      for (std::size_t b = 0; b < next_.size(); ++b) perturbed_[b] = next_[b];
      bool moved = false;
      for (const int j : bodies) {
        if (!moves(j, k)) continue;
        moved = true;
        core::BodyState& sj = perturbed_[static_cast<std::size_t>(j)];
        if (k < 3) {
          sj.p_WBr(k) += eps;
          sj.v_WBr(k) += eps * gamma_prime;
        } else if (k < 6) {
          // configuration q exp(ε (T e_k)~), velocity W + ε γ' e_k
          const Matrix3d T = rotation::right_jacobian(z.segment<3>(offset(j) + 3));
          sj.theta_WB = rotation::quaternion_multiply(sj.theta_WB,
                                                      rotation::exp_quaternion(eps * T.col(k - 3)));
          renormalize_unit_product(sj.theta_WB);
          sj.w_WB_B(k - 3) += eps * gamma_prime;
        } else {
          sj.q_f(k - 6) += eps;
          sj.qd_f(k - 6) += eps * gamma_prime;
        }
      }
      if (!moved) continue;
      const core::Loads loads = model_.compute_wrenches(context, perturbed_, ws_);
      ++evaluations_;
      for (int i = 0; i < n_bodies_; ++i) {
        const int j = source_[static_cast<std::size_t>(i)];
        if (j < 0 || !moves(j, k)) continue;
        const Eigen::Index column = offset(j) + k;
        const core::Body& body_i = model_.body(i);
        const auto oi = static_cast<Eigen::Index>(offset(i));
        const auto ii = static_cast<std::size_t>(i);
        if (body_i.is_flexible()) {
          body_residual(i, loads);
          const Eigen::Index width_i = offset(i + 1) - offset(i);
          for (Eigen::Index row = 0; row < width_i; ++row) {
            if (!integrated_row(i, static_cast<int>(row))) continue;
            S.coeffRef(oi + row, column) +=
                (bh2 / eps) * (body_residual_[ii](row) - body_residual_base_[ii](row));
          }
          continue;
        }
        if (body_i.is_prescribed()) continue;
        const core::Wrench& w0 = wrenches_[ii];
        const core::Wrench& w1 = ws_.wrenches[ii];
        if (body_i.is_free()) {
          const Vector3d df = (bh2 / eps) * (w1.f_W - w0.f_W);
          for (Eigen::Index r = 0; r < 3; ++r) S.coeffRef(oi + r, column) -= df(r);
        }
        const Vector3d dtau = (bh2 / eps) * (R_[ii].transpose() * (w1.tau_Br_W - w0.tau_Br_W));
        for (Eigen::Index r = 0; r < 3; ++r) S.coeffRef(oi + 3 + r, column) -= dtau(r);
      }
      if (n_multipliers_ > 0) {
        model_.constraints()->evaluate(context.t, ws_.kinematics, model_.velocity_layout(),
                                       rows_perturbed_);
        jt_lambda_perturbed_.setZero();
        add_rows_transpose(rows_perturbed_, z, jt_lambda_perturbed_, nullptr);
        for (int b = 0; b < n_bodies_; ++b) {
          const int j = source_[static_cast<std::size_t>(b)];
          if (j < 0 || !moves(j, k)) continue;
          const Eigen::Index column = offset(j) + k;
          for (int row = offset(b); row < offset(b + 1); ++row) {
            if (!integrated_row(b, row - offset(b))) continue;
            S.coeffRef(row, column) += (jt_lambda_perturbed_(row) - jt_lambda_(row)) / eps;
          }
        }
      }
    }
  }
  for (std::size_t b = 0; b < next_.size(); ++b) perturbed_[b] = next_[b];
  // Leave the flexible bodies' residuals as they were at z (the last residual call).
  for (int b = 0; b < n_bodies_; ++b) {
    if (model_.body(b).is_flexible()) {
      body_residual_[static_cast<std::size_t>(b)] =
          body_residual_base_[static_cast<std::size_t>(b)];
    }
  }
  if (n_multipliers_ == 0) return;
  // Joint blocks: Jᵀ in the dynamic rows, J T in the constraint rows (integrated unknowns).
  for (int a = 0; a < n_multipliers_; ++a) {
    const int row = active_[static_cast<std::size_t>(a)];
    for (const int b : model_.constraints()->row_bodies(row)) {
      if (b < 0) continue;
      const auto o = static_cast<Eigen::Index>(offset(b));
      const Eigen::Index width = offset(b + 1) - offset(b);
      const Matrix3d T = rotation::right_jacobian(z.segment<3>(o + 3));
      const auto J_b = row_block(rows_.jacobian, row, b);
      for (Eigen::Index k = 0; k < width; ++k) {
        if (!integrated_row(b, static_cast<int>(k))) continue;
        S.coeffRef(o + k, n + a) = J_b(k);
        if (k < 3 || k >= 6) S.coeffRef(n + a, o + k) = J_b(k);
      }
      if (integrated_row(b, 3)) {
        const Eigen::RowVector3d JT = J_b.segment<3>(3).transpose() * T;
        for (Eigen::Index c = 0; c < 3; ++c) S.coeffRef(n + a, o + 3 + c) = JT(c);
      }
    }
  }
}

}  // namespace flexref::lie::detail
