#include "constraint/reduced_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "constraint/small_cholesky.hpp"
#include "core/orientation_test_tpl.hpp"
#include "core/row_selection_tpl.hpp"
#include "core/schur_complement_tpl.hpp"

namespace flexref::constraint {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

/// The sign of det(a) by Gaussian elimination with partial pivoting, in place (a is destroyed):
/// +1, −1, or 0 where a pivot is exactly zero. For the orientation test's r × r product, where
/// a library LU's dispatch costs more than the arithmetic.
int determinant_sign(Eigen::MatrixXd& a) {
  const Eigen::Index n = a.rows();
  int sign = 1;
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Index pivot = k;
    for (Eigen::Index i = k + 1; i < n; ++i) {
      if (std::abs(a(i, k)) > std::abs(a(pivot, k))) pivot = i;
    }
    if (!(a(pivot, k) != 0.0)) return 0;
    if (pivot != k) {
      a.row(k).swap(a.row(pivot));
      sign = -sign;
    }
    if (a(k, k) < 0.0) sign = -sign;
    for (Eigen::Index i = k + 1; i < n; ++i) {
      const double factor = a(i, k) / a(k, k);
      for (Eigen::Index j = k + 1; j < n; ++j) a(i, j) -= factor * a(k, j);
    }
  }
  return sign;
}

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

/// The independent rows of J_c (core::independent_rows), the rows that vanish on the tree's
/// coordinates set to zero first: a row below kRedundantRowTolerance of its own scale
/// Σ_b |J_rb| |S_b| (the rows' blocks on the bodies, S's rows of the bodies) is satisfied by the
/// tree's joints identically — a distance between two points a spherical joint already holds, a
/// fixed joint's position rows between two bodies hinged on one axis — and its rounding, scaled to
/// unit length by the rank decision, would look independent.
std::vector<int> independent_rows_of(Eigen::MatrixXd J_c, const Eigen::VectorXd& scale) {
  for (Eigen::Index r = 0; r < J_c.rows(); ++r) {
    if (J_c.row(r).norm() <= core::kRedundantRowTolerance * scale(r)) J_c.row(r).setZero();
  }
  return core::independent_rows<double>(J_c);
}

/// J_c = J S and γ_c = γ − J Ṡ u on the closure rows r with (*evaluated)[r] ≠ 0 (null: all),
/// row by row over its two bodies' blocks of J (`rows` evaluated at the poses of `tree`); J_c's
/// other rows zero.
void assemble_closures(const IdealJoints& closures, const TreeKinematics& kinematics,
                       const TreeWorkspace& tree, const core::ConstraintRows& rows,
                       const std::vector<char>* evaluated, Eigen::MatrixXd& J_c,
                       Eigen::VectorXd& gamma_c) {
  J_c.setZero();
  for (int r = 0; r < closures.row_count(); ++r) {
    if (evaluated != nullptr && (*evaluated)[static_cast<std::size_t>(r)] == 0) continue;
    double gamma = rows.gamma(r);
    for (int slot = 0; slot < 2; ++slot) {
      const int b = rows.jacobian.slot(r, slot).body;
      if (b < 0) continue;
      const Eigen::Index o = 6 * static_cast<Eigen::Index>(b);
      const Vector6 J_rb = rows.jacobian.values(r, slot).head<6>();
      gamma -= J_rb.dot(tree.bias.segment<6>(o));
      for (const int i : kinematics.body_columns(b)) {
        J_c(r, i) += J_rb.dot(tree.S.block<6, 1>(o, i));
      }
    }
    gamma_c(r) = gamma;
  }
}

}  // namespace

ReducedModel::ReducedModel(const core::Model& model) : ReducedModel(model, model.initial_state()) {}

ReducedModel::ReducedModel(const core::Model& model, const core::State& initial)
    : model_(&model),
      kinematics_(spanning_tree(model.bodies(), model_joints(model), initial), model.bodies()) {
  kinematics_.coordinates(initial, q0_, u0_);
  const std::vector<IdealJointSpec>& joints = model_joints(model);
  std::vector<IdealJointSpec> closures;
  for (const int j : kinematics_.tree().closures) {
    closures.push_back(joints[static_cast<std::size_t>(j)]);
  }
  if (closures.empty()) return;
  closures_ = std::make_unique<IdealJoints>(std::move(closures), model.num_bodies());
  // The independent closure rows at the consistent initial state, by the maximal model's rule.
  ReducedWorkspace ws = make_workspace();
  kinematics_.evaluate(q0_, u0_, ws.tree);
  model.compute_wrenches({0.0, 0.0}, ws.tree.state, ws.tree.R_WB, ws.model);
  std::fill(ws.evaluated.begin(), ws.evaluated.end(), 1);
  evaluate_closures(0.0, u0_, 0.0, ws);
  active_ = independent_closure_rows(ws);
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
  Eigen::Index columns = 0;
  for (int b = 0; b < model.num_bodies(); ++b) {
    columns += static_cast<Eigen::Index>(kinematics_.body_columns(b).size());
  }
  ws.MS = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, columns);
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
  ws.accepted_rows = Eigen::MatrixXd::Zero(r, nu);
  ws.row_norms = Eigen::MatrixXd::Zero(r, 2);
  ws.chosen.reserve(static_cast<std::size_t>(m));
  ws.solved.reserve(static_cast<std::size_t>(m));
  ws.crossing = Eigen::MatrixXd::Identity(r, r);
  ws.evaluated.assign(static_cast<std::size_t>(m), 0);
  ws.q = Vector::Zero(position_count());
  ws.u = Vector::Zero(nu);
  if (closures_) {
    ws.accepted_tree = kinematics_.make_workspace();
    ws.accepted_kinematics = ws.model.kinematics;
    ws.accepted_closures.resize_sparse(m);
    closures_->prepare_rows(model.velocity_layout(), ws.accepted_closures);
    ws.accepted_J_c = Eigen::MatrixXd::Zero(m, nu);
    ws.accepted_gamma_c = Vector::Zero(m);
  }
  return ws;
}

void ReducedModel::accelerations(const core::LoadContext& context, const Vector& q, const Vector& u,
                                 ReducedWorkspace& ws, Vector& u_dot, double stabilization,
                                 const ClosureTracker* tracker) const {
  const core::Model& model = *model_;
  ws.t = context.t;
  ws.q = q;
  ws.u = u;
  // The bodies' Euler parameters are left to attitudes(): the loads and the closures read the
  // tree's attitude matrices.
  kinematics_.evaluate(q, u, ws.tree, false);
  const core::Loads loads = model.compute_wrenches(context, ws.tree.state, ws.tree.R_WB, ws.model);
  // r(Ṡu) = M Ṡ u − Q body by body (the model's own equations); then, over each body's columns
  // of S (its ancestors'), M_r = Σ_b S_bᵀ M_b S_b and Q_r = Σ_b −S_bᵀ r_b(Ṡu).
  ws.M_r.setZero();
  ws.Q_r.setZero();
  const int n = model.num_bodies();
  // Two passes: the residuals and the products M_b S_i first, the sums after, so that no sum
  // reads a vector still on its way to memory (stored in halves of other widths than the sums'
  // loads, which store-to-load forwarding does not serve: the largest stall of the evaluation).
  Eigen::Index column = 0;
  for (int b = 0; b < n; ++b) {
    const auto k = static_cast<std::size_t>(b);
    const Eigen::Index o = 6 * static_cast<Eigen::Index>(b);
    ws.bias[k].a_WBr = ws.tree.bias.segment<3>(o);
    ws.bias[k].alpha_WB_B = ws.tree.bias.segment<3>(o + 3);
    model.dynamics_residual(b, loads, ws.bias[k], ws.model, ws.residual.segment(o, 6));
    const core::Body& body = model.body(b);
    for (const int i : kinematics_.body_columns(b)) {
      const auto S_i = ws.tree.S.block<6, 1>(o, i);
      auto MS_i = ws.MS.col(column++);
      MS_i.head<3>() = body.mass() * S_i.head<3>();
      MS_i.tail<3>().noalias() = body.I_Br_B() * S_i.tail<3>();
    }
  }
  column = 0;
  for (int b = 0; b < n; ++b) {
    const Eigen::Index o = 6 * static_cast<Eigen::Index>(b);
    const Vector6 r_b = ws.residual.segment<6>(o);
    const std::vector<int>& columns = kinematics_.body_columns(b);
    for (std::size_t x = 0; x < columns.size(); ++x) {
      const int i = columns[x];
      const Vector6 S_i = ws.tree.S.block<6, 1>(o, i);
      const Vector6 MS_i = ws.MS.col(column++);
      ws.Q_r(i) -= S_i.dot(r_b);
      for (std::size_t y = 0; y <= x; ++y) {
        const int j = columns[y];
        ws.M_r(i, j) += ws.tree.S.block<6, 1>(o, j).dot(MS_i);
      }
    }
  }
  // M_r = L Lᵀ in place (reads the lower triangle, leaves L − diag(L) there).
  if (cholesky_in_place(ws.M_r, ws.M_r_inv_diag.data()) >= 0) {
    throw std::runtime_error("reduced model: the tree's mass matrix is not positive definite");
  }
  u_dot = ws.Q_r;
  forward_substitute(ws.M_r, ws.M_r_inv_diag.data(), u_dot.data());
  back_substitute(ws.M_r, ws.M_r_inv_diag.data(), u_dot.data());
  if (active_.empty()) return;
  const double a = stabilization;
  // The rows in force: the tracker's, or rows of this evaluation's own where they became
  // ill-conditioned (core::choose_rows' rule on J_c). The closures are evaluated on the rows in
  // force alone; a choice of rows evaluates them all (choose_closure_rows).
  const std::vector<int>* rows = tracker != nullptr ? &tracker->rows : &active_;
  const double reference_ratio = tracker != nullptr ? tracker->selection_ratio : 0.0;
  std::fill(ws.evaluated.begin(), ws.evaluated.end(), 0);
  for (const int row : *rows) ws.evaluated[static_cast<std::size_t>(row)] = 1;
  evaluate_closures(context.t, u, a, ws);
  ws.rows_chosen = false;
  ws.pivot_ratio = factor_closures(*rows, ws);
  if (!(ws.pivot_ratio >= core::kReselectPivotRatio &&
        ws.pivot_ratio >= core::kReselectPivotFall * reference_ratio)) {
    if (!choose_closure_rows(context.t, u, a, ws)) throw_singular(*rows, ws, context.t);
    rows = &ws.chosen;
  }
  if (!(ws.pivot_ratio >= core::kSingularPivotRatio)) throw_singular(*rows, ws, context.t);
  ws.rows_turned = false;
  int turn = tracker != nullptr && tracker->has_accepted ? orientation(*rows, *tracker, ws) : 1;
  if (turn < 0) {
    // Rows that alone turned through a dependency among themselves, while all rows kept their
    // rank, are replaced by rows chosen here, which keep the orientation (check_orientation's
    // rule); otherwise the mechanism passed a singular configuration since the accepted state.
    if (rows == &ws.chosen || !choose_closure_rows(context.t, u, a, ws)) {
      throw_passed_singular(*rows, ws, tracker->accepted_time, context.t);
    }
    rows = &ws.chosen;
    if (!(ws.pivot_ratio >= core::kSingularPivotRatio)) throw_singular(*rows, ws, context.t);
    turn = orientation(*rows, *tracker, ws);
    if (turn < 0) throw_passed_singular(*rows, ws, tracker->accepted_time, context.t);
  }
  // The test is not conclusive where a row turned by more than its angle: the step from the
  // accepted state was too long for it (a motion the tree's coordinates follow exactly, such as
  // a parallelogram's, lets Adams take steps of many radians), and the integrator takes a shorter
  // one.
  ws.rows_turned = turn == 0;
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const auto row = static_cast<Eigen::Index>((*rows)[i]);
    const auto k = static_cast<Eigen::Index>(i);
    // (J_a M_r⁻¹ J_aᵀ) λ = J_a u̇₀ − γ_a (γ_a with Baumgarte's term).
    double g = ws.gamma_c(row);
    if (a != 0.0) g -= 2.0 * a * ws.velocity_rows(row) + a * a * ws.rows.phi(row);
    ws.rhs(k) = ws.J_a.row(k).dot(u_dot) - g;
  }
  ws.lambda = ws.rhs;
  forward_substitute(ws.A, ws.A_inv_diag.data(), ws.lambda.data());
  back_substitute(ws.A, ws.A_inv_diag.data(), ws.lambda.data());
  ws.correction.noalias() = ws.W.transpose() * ws.lambda;
  back_substitute(ws.M_r, ws.M_r_inv_diag.data(), ws.correction.data());
  u_dot -= ws.correction;
  ws.solved.assign(rows->begin(), rows->end());
}

double ReducedModel::factor_closures(const std::vector<int>& rows, ReducedWorkspace& ws) const {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ws.J_a.row(static_cast<Eigen::Index>(i)) = ws.J_c.row(static_cast<Eigen::Index>(rows[i]));
  }
  ws.W = ws.J_a;
  forward_substitute_rows(ws.M_r, ws.M_r_inv_diag.data(), ws.W);
  // A = W Wᵀ = Σ_k w_k w_kᵀ (w_k: W's contiguous column k), column by column of A (whole
  // columns: a loop over the lower triangle alone ran more instructions). Its diagonal, |w_i|²,
  // is also the orientation test's.
  ws.A.setZero();
  for (Eigen::Index k = 0; k < ws.W.cols(); ++k) {
    const double* w_k = ws.W.col(k).data();
    for (Eigen::Index j = 0; j < ws.A.cols(); ++j) {
      // W keeps the closures' structural zeros (a row's loop reaches a few tree coordinates):
      // their terms would add zeros, which leave a sum started at +0 as it is.
      if (w_k[j] == 0.0) continue;
      double* a_j = ws.A.col(j).data();
      for (Eigen::Index i = 0; i < ws.A.rows(); ++i) a_j[i] += w_k[i] * w_k[j];
    }
  }
  ws.row_norms.col(1) = ws.A.diagonal();
  ws.schur_failed = cholesky_in_place(ws.A, ws.A_inv_diag.data(), ws.A_diag.data());
  if (ws.schur_failed >= 0) return 0.0;
  const double ratio = ws.A_diag.minCoeff() / ws.A_diag.maxCoeff();
  return std::isfinite(ratio) ? ratio * ratio : 0.0;
}

void ReducedModel::evaluate_closures(double t, const Vector& u, double a,
                                     ReducedWorkspace& ws) const {
  closures_->evaluate_rows(t, ws.model.kinematics, model_->velocity_layout(), ws.evaluated,
                           ws.rows);
  assemble_closures(*closures_, kinematics_, ws.tree, ws.rows, &ws.evaluated, ws.J_c, ws.gamma_c);
  if (a != 0.0) {
    ws.velocity_rows = ws.rows.phi_t;
    ws.velocity_rows.noalias() += ws.J_c * u;
  }
}

void ReducedModel::evaluate_accepted_closures(const ClosureTracker& tracker,
                                              ReducedWorkspace& ws) const {
  kinematics_.evaluate(tracker.q, tracker.u, ws.accepted_tree, false);
  pose_bodies(ws.accepted_tree, ws.accepted_kinematics);
  closures_->evaluate(tracker.evaluated_time, ws.accepted_kinematics, model_->velocity_layout(),
                      ws.accepted_closures);
  assemble_closures(*closures_, kinematics_, ws.accepted_tree, ws.accepted_closures, nullptr,
                    ws.accepted_J_c, ws.accepted_gamma_c);
}

void ReducedModel::pose_bodies(const TreeWorkspace& tree,
                               std::vector<core::BodyKinematics>& bodies) const {
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    bodies[b].state = &tree.state[b];
    bodies[b].R_WB = tree.R_WB[b];
    bodies[b].q_f = &tree.state[b].q_f;
  }
}

std::vector<int> ReducedModel::independent_closure_rows(const ReducedWorkspace& ws) const {
  // Each row's own scale Σ_b |J_rb| |S_b|, for the rows the tree satisfies identically.
  Eigen::VectorXd scale = Eigen::VectorXd::Zero(ws.J_c.rows());
  for (int r = 0; r < closures_->row_count(); ++r) {
    for (int slot = 0; slot < 2; ++slot) {
      const int b = ws.rows.jacobian.slot(r, slot).body;
      if (b < 0) continue;
      scale(r) += ws.rows.jacobian.values(r, slot).head<6>().norm() *
                  ws.tree.S.middleRows<6>(6 * static_cast<Eigen::Index>(b)).norm();
    }
  }
  return independent_rows_of(ws.J_c, scale);
}

bool ReducedModel::choose_closure_rows(double t, const Vector& u, double a,
                                       ReducedWorkspace& ws) const {
  // The choice reads every row: those not in force are evaluated too (the rows in force again,
  // to the same bits).
  std::fill(ws.evaluated.begin(), ws.evaluated.end(), 1);
  evaluate_closures(t, u, a, ws);
  ws.rows_chosen = true;
  ws.chosen = independent_closure_rows(ws);
  // The rank cannot grow for a mechanism that moves continuously (core::choose_rows).
  if (ws.chosen.size() < active_.size()) return false;
  ws.chosen.resize(active_.size());
  ws.pivot_ratio = factor_closures(ws.chosen, ws);
  return true;
}

int ReducedModel::orientation(const std::vector<int>& rows, const ClosureTracker& tracker,
                              ReducedWorkspace& ws) const {
  const auto r = static_cast<Eigen::Index>(rows.size());
  const Eigen::Index n = ws.W.cols();
  // The accepted J_c's rows: the tracker's, or where rows chosen here were not in force at the
  // accepted state, that state's closures evaluated again (all rows, the same bits).
  const Eigen::MatrixXd* J_accepted = &tracker.J_accepted;
  for (const int row : rows) {
    if (tracker.evaluated[static_cast<std::size_t>(row)] == 0) {
      evaluate_accepted_closures(tracker, ws);
      J_accepted = &ws.accepted_J_c;
      break;
    }
  }
  // X = J_a,accepted L⁻ᵀ beside W = J_a L⁻ᵀ: J_a,accepted M_r⁻¹ J_aᵀ = X Wᵀ, and each row's turn
  // is read in M_r⁻¹'s metric, cos = x_i · w_i / (|x_i| |w_i|), column by column of the
  // column-major X and W.
  for (Eigen::Index k = 0; k < n; ++k) {
    for (Eigen::Index i = 0; i < r; ++i) {
      ws.accepted_rows(i, k) = (*J_accepted)(rows[static_cast<std::size_t>(i)], k);
    }
  }
  forward_substitute_rows(ws.M_r, ws.M_r_inv_diag.data(), ws.accepted_rows);
  // |w_i|² is A's diagonal, which factor_closures kept in row_norms' second column.
  ws.crossing.setZero();
  ws.row_norms.col(0).setZero();
  for (Eigen::Index k = 0; k < n; ++k) {
    const double* x_k = ws.accepted_rows.col(k).data();
    const double* w_k = ws.W.col(k).data();
    for (Eigen::Index j = 0; j < r; ++j) {
      if (w_k[j] == 0.0) continue;  // a structural zero of W, as in factor_closures
      double* c_j = ws.crossing.col(j).data();
      for (Eigen::Index i = 0; i < r; ++i) c_j[i] += x_k[i] * w_k[j];
    }
    for (Eigen::Index i = 0; i < r; ++i) ws.row_norms(i, 0) += x_k[i] * x_k[i];
  }
  for (Eigen::Index i = 0; i < r; ++i) {
    const double cosine = core::kOrientationTestCosine;
    if (ws.crossing(i, i) < cosine * std::sqrt(ws.row_norms(i, 0) * ws.row_norms(i, 1))) return 0;
  }
  return determinant_sign(ws.crossing) > 0 ? 1 : -1;
}

void ReducedModel::throw_singular(const std::vector<int>& rows, const ReducedWorkspace& ws,
                                  double t) const {
  const std::string name = closures_->joint_name(smallest_pivot_joint(rows, ws));
  throw core::SingularConfigurationError(
      name, t,
      "singular configuration at t = " + std::to_string(t) + ": the constraints of joint '" + name +
          "' became dependent on the others (smallest/largest pivot of J M^-1 J^T " +
          std::to_string(ws.pivot_ratio) +
          "); the mechanism is at a dead point or a bifurcation, where its multipliers and "
          "motion are not determined");
}

void ReducedModel::throw_passed_singular(const std::vector<int>& rows, const ReducedWorkspace& ws,
                                         double t0, double t1) const {
  const std::string name = closures_->joint_name(smallest_pivot_joint(rows, ws));
  throw core::SingularConfigurationError(
      name, t1,
      "singular configuration passed between t = " + std::to_string(t0) +
          " and t = " + std::to_string(t1) + ": the constraints of joint '" + name +
          "' became dependent on the others there (the rows' orientation turned; smallest/largest "
          "pivot of J M^-1 J^T now " +
          std::to_string(ws.pivot_ratio) +
          "); the mechanism passed a dead point or a bifurcation, where its multipliers and "
          "motion are not determined");
}

int ReducedModel::smallest_pivot_joint(const std::vector<int>& rows,
                                       const ReducedWorkspace& ws) const {
  if (rows.empty()) return 0;
  Eigen::Index at = ws.schur_failed;
  if (at < 0) ws.A_diag.minCoeff(&at);
  return closures_->joint_of_row(rows[static_cast<std::size_t>(at)]);
}

ClosureTracker ReducedModel::make_tracker() const {
  ClosureTracker tracker;
  tracker.rows = active_;
  const int m = closures_ ? closures_->row_count() : 0;
  tracker.J_accepted = Eigen::MatrixXd::Zero(m, velocity_count());
  tracker.evaluated.assign(static_cast<std::size_t>(m), 0);
  tracker.q = Vector::Zero(position_count());
  tracker.u = Vector::Zero(velocity_count());
  return tracker;
}

void ReducedModel::accept(double t, const ReducedWorkspace& ws, ClosureTracker& tracker) const {
  if (active_.empty()) return;
  if (ws.rows_chosen) {
    tracker.rows = ws.solved;
    tracker.selection_ratio = ws.pivot_ratio;
  } else if (!(tracker.selection_ratio > 0.0)) {
    tracker.selection_ratio = ws.pivot_ratio;
  }
  tracker.J_accepted = ws.J_c;
  tracker.evaluated = ws.evaluated;
  tracker.evaluated_time = ws.t;
  tracker.q = ws.q;
  tracker.u = ws.u;
  tracker.accepted_time = t;
  tracker.has_accepted = true;
}

void ReducedModel::closure_force(const ReducedWorkspace& ws, Vector& force) const {
  force.setZero();
  if (active_.empty()) return;
  for (std::size_t i = 0; i < ws.solved.size(); ++i) {
    const int r = ws.solved[i];
    const double lambda = ws.lambda(static_cast<Eigen::Index>(i));
    for (int slot = 0; slot < 2; ++slot) {
      const int b = ws.rows.jacobian.slot(r, slot).body;
      if (b < 0) continue;
      force.segment<6>(6 * static_cast<Eigen::Index>(b)) -=
          lambda * ws.rows.jacobian.values(r, slot).head<6>();
    }
  }
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
