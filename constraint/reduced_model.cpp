#include "constraint/reduced_model.hpp"

#include <stdexcept>
#include <string>

#include "constraint/small_cholesky.hpp"
#include "core/row_selection_tpl.hpp"
#include "core/schur_complement_tpl.hpp"

namespace flexref::constraint {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

/// The model's ideal joints, or an empty list; refuses what the reduced form cannot carry.
const std::vector<IdealJointSpec>& model_joints(const core::Model& model) {
  static const std::vector<IdealJointSpec> none;
  for (const auto& element : model.elements()) {
    if (element->switching_function_count() > 0 || element->wear_depth_count() > 0) {
      throw std::invalid_argument(
          "a contact element (switching functions or worn depths): the reduced form has no event "
          "location; use the maximal form");
    }
  }
  if (!model.has_constraints()) return none;
  const auto* joints = dynamic_cast<const IdealJoints*>(model.constraints());
  if (joints == nullptr) {
    throw std::invalid_argument("the model's constraints are not ideal joints");
  }
  return joints->joints();
}

TreeKinematics make_kinematics(const core::Model& model) {
  return TreeKinematics(spanning_tree(model.bodies(), model_joints(model), model.initial_state()),
                        model.bodies());
}

}  // namespace

ReducedModel::ReducedModel(const core::Model& model)
    : model_(&model), kinematics_(make_kinematics(model)) {
  const std::vector<IdealJointSpec>& joints = model_joints(model);
  std::vector<IdealJointSpec> closures;
  for (const int j : kinematics_.tree().closures) {
    closures.push_back(joints[static_cast<std::size_t>(j)]);
  }
  if (closures.empty()) return;
  closures_ = std::make_unique<IdealJoints>(std::move(closures), model.num_bodies());
  // The independent closure rows at the consistent initial state, by the maximal model's rule.
  ReducedWorkspace ws = make_workspace();
  Vector q, u, u_dot(velocity_count());
  coordinates(model.initial_state(), q, u);
  kinematics_.evaluate(q, u, ws.tree);
  model.compute_wrenches({0.0, 0.0}, ws.tree.state, ws.model);
  core::ConstraintRows rows;
  rows.resize(closures_->row_count(), model.velocity_layout().size());
  closures_->evaluate(0.0, ws.model.kinematics, model.velocity_layout(), rows);
  ws.J_c.noalias() = rows.J * ws.tree.S;
  active_ = core::independent_rows<double>(ws.J_c);
}

ReducedWorkspace ReducedModel::make_workspace() const {
  const core::Model& model = *model_;
  ReducedWorkspace ws;
  ws.tree = kinematics_.make_workspace();
  ws.model = model.make_workspace();
  const int n6 = model.velocity_layout().size();
  const int nu = velocity_count();
  const int m = closures_ ? closures_->row_count() : 0;
  const auto r = static_cast<Eigen::Index>(active_.size());
  if (closures_) {
    ws.rows.resize_sparse(m);
    closures_->prepare_rows(model.velocity_layout(), ws.rows);
  }
  ws.bias = model.make_accelerations();
  ws.residual = Vector::Zero(n6);
  ws.M_r = Eigen::MatrixXd::Zero(nu, nu);
  ws.Q_r = Vector::Zero(nu);
  ws.J_c = Eigen::MatrixXd::Zero(m, nu);
  ws.gamma_c = Vector::Zero(m);
  ws.velocity_rows = Vector::Zero(m);
  ws.J_a = Eigen::MatrixXd::Zero(r, nu);
  ws.rhs = Vector::Zero(r);
  ws.lambda = Vector::Zero(r);
  ws.W = Eigen::MatrixXd::Zero(r, nu);
  ws.A = Eigen::MatrixXd::Zero(r, r);
  ws.correction = Vector::Zero(nu);
  ws.M_r_inv_diag = Vector::Zero(nu);
  ws.A_inv_diag = Vector::Zero(r);
  ws.A_diag = Vector::Zero(r);
  return ws;
}

void ReducedModel::accelerations(const core::LoadContext& context, const Vector& q, const Vector& u,
                                 ReducedWorkspace& ws, Vector& u_dot, double stabilization) const {
  const core::Model& model = *model_;
  kinematics_.evaluate(q, u, ws.tree);
  const core::Loads loads = model.compute_wrenches(context, ws.tree.state, ws.model);
  // r(Ṡu) = M Ṡ u − Q body by body (the model's own equations); then, over each body's columns
  // of S (its ancestors'), M_r = Σ_b S_bᵀ M_b S_b and Q_r = Σ_b −S_bᵀ r_b(Ṡu).
  ws.M_r.setZero();
  ws.Q_r.setZero();
  const int n = model.num_bodies();
  for (int b = 0; b < n; ++b) {
    const auto k = static_cast<std::size_t>(b);
    const Eigen::Index o = 6 * static_cast<Eigen::Index>(b);
    ws.bias[k].a_WBr = ws.tree.bias.segment<3>(o);
    ws.bias[k].alpha_WB_B = ws.tree.bias.segment<3>(o + 3);
    model.dynamics_residual(b, loads, ws.bias[k], ws.model, ws.residual.segment(o, 6));
    const core::Body& body = model.body(b);
    const Vector6 r_b = ws.residual.segment<6>(o);
    const std::vector<int>& columns = kinematics_.body_columns(b);
    for (std::size_t x = 0; x < columns.size(); ++x) {
      const int i = columns[x];
      const Vector6 S_i = ws.tree.S.block<6, 1>(o, i);
      Vector6 MS_i;
      MS_i.head<3>() = body.mass() * S_i.head<3>();
      MS_i.tail<3>().noalias() = body.I_Br_B() * S_i.tail<3>();
      ws.Q_r(i) -= S_i.dot(r_b);
      for (std::size_t y = 0; y <= x; ++y) {
        const int j = columns[y];
        ws.M_r(i, j) += ws.tree.S.block<6, 1>(o, j).dot(MS_i);
      }
    }
  }
  if (cholesky_in_place(ws.M_r, ws.M_r_inv_diag.data()) >=
      0) {  // reads the lower triangle, leaves L there
    throw std::runtime_error("reduced model: the tree's mass matrix is not positive definite");
  }
  u_dot = ws.Q_r;
  forward_substitute(ws.M_r, ws.M_r_inv_diag.data(), u_dot.data());
  back_substitute(ws.M_r, ws.M_r_inv_diag.data(), u_dot.data());
  if (active_.empty()) return;
  // The closures: J_c = J S, γ_c = γ − J Ṡ u, row by row over its two bodies' blocks of J.
  closures_->evaluate(context.t, ws.model.kinematics, model.velocity_layout(), ws.rows);
  ws.J_c.setZero();
  for (int r = 0; r < closures_->row_count(); ++r) {
    double gamma = ws.rows.gamma(r);
    for (int slot = 0; slot < 2; ++slot) {
      const int b = ws.rows.jacobian.slot(r, slot).body;
      if (b < 0) continue;
      const Eigen::Index o = 6 * static_cast<Eigen::Index>(b);
      const Vector6 J_rb = ws.rows.jacobian.values(r, slot).head<6>();
      gamma -= J_rb.dot(ws.tree.bias.segment<6>(o));
      for (const int i : kinematics_.body_columns(b)) {
        ws.J_c(r, i) += J_rb.dot(ws.tree.S.block<6, 1>(o, i));
      }
    }
    ws.gamma_c(r) = gamma;
  }
  const double a = stabilization;
  if (a != 0.0) {
    ws.velocity_rows = ws.rows.phi_t;
    ws.velocity_rows.noalias() += ws.J_c * u;
  }
  for (std::size_t i = 0; i < active_.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(active_[i]);
    const auto k = static_cast<Eigen::Index>(i);
    ws.J_a.row(k) = ws.J_c.row(row);
    // (J_a M_r⁻¹ J_aᵀ) λ = J_a u̇₀ − γ_a (γ_a with Baumgarte's term).
    double g = ws.gamma_c(row);
    if (a != 0.0) g -= 2.0 * a * ws.velocity_rows(row) + a * a * ws.rows.phi(row);
    ws.rhs(k) = ws.J_a.row(k).dot(u_dot) - g;
  }
  ws.W = ws.J_a;
  forward_substitute_rows(ws.M_r, ws.M_r_inv_diag.data(), ws.W);
  // A = W Wᵀ = Σ_k w_k w_kᵀ (w_k: W's contiguous column k), column by column of A.
  ws.A.setZero();
  for (Eigen::Index k = 0; k < ws.W.cols(); ++k) {
    const double* w_k = ws.W.col(k).data();
    for (Eigen::Index j = 0; j < ws.A.cols(); ++j) {
      double* a_j = ws.A.col(j).data();
      for (Eigen::Index i = 0; i < ws.A.rows(); ++i) a_j[i] += w_k[i] * w_k[j];
    }
  }
  const Eigen::Index failed = cholesky_in_place(ws.A, ws.A_inv_diag.data(), ws.A_diag.data());
  const auto& pivots = ws.A_diag;
  const double smallest = pivots.minCoeff();
  if (failed >= 0 ||
      !(smallest * smallest >= core::kSingularPivotRatio * pivots.maxCoeff() * pivots.maxCoeff())) {
    Eigen::Index at = failed;
    if (failed < 0) pivots.minCoeff(&at);
    const int joint = closures_->joint_of_row(active_[static_cast<std::size_t>(at)]);
    throw core::SingularConfigurationError(closures_->joint_name(joint), context.t,
                                           "reduced model: the closure rows of joint '" +
                                               closures_->joint_name(joint) +
                                               "' lost rank (a singular configuration)");
  }
  ws.lambda = ws.rhs;
  forward_substitute(ws.A, ws.A_inv_diag.data(), ws.lambda.data());
  back_substitute(ws.A, ws.A_inv_diag.data(), ws.lambda.data());
  ws.correction.noalias() = ws.W.transpose() * ws.lambda;
  back_substitute(ws.M_r, ws.M_r_inv_diag.data(), ws.correction.data());
  u_dot -= ws.correction;
}

void ReducedModel::body_accelerations(const ReducedWorkspace& ws, const Vector& u_dot,
                                      core::Accelerations& accelerations) const {
  for (int b = 0; b < model_->num_bodies(); ++b) {
    const Eigen::Index o = 6 * static_cast<Eigen::Index>(b);
    core::BodyAcceleration& acc = accelerations[static_cast<std::size_t>(b)];
    acc.a_WBr = ws.tree.bias.segment<3>(o);
    acc.a_WBr.noalias() += ws.tree.S.middleRows<3>(o) * u_dot;
    acc.alpha_WB_B = ws.tree.bias.segment<3>(o + 3);
    acc.alpha_WB_B.noalias() += ws.tree.S.middleRows<3>(o + 3) * u_dot;
  }
}

}  // namespace flexref::constraint
