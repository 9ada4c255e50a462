#pragma once
/// \file model_initial_state_impl.hpp
/// ModelTpl<S>'s initial state with ideal joints (docs/joints.md, "Initial state" and "What a
/// jointed solution promises"): the independent rows chosen at the scene's initial
/// configuration, joint data double cannot resolve refused, the projection onto the joints and
/// its checks (every row reached, redundant rows told apart from a singular start). Included by
/// model_impl.hpp.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/model.hpp"

namespace flexref::core {

/// A joint point farther from its free body's reference point than this many of the body's
/// smallest radii of gyration ρ (about Br) is beyond what the constrained solve resolves: a
/// length row's weight in the Schur complement J M⁻¹ Jᵀ is 1/m from the body's translation and
/// ~(r/ρ)²/m from its rotation, so the complement's pivots spread by (r/ρ)², which must stay
/// above the singular-configuration test kSingularPivotRatio = 1e-12 with a margin of 100:
/// r/ρ ≤ 1e5. Beyond (r/ρ)² = 1/ε the translation's part is round-off of the rotation's and the
/// rows decide nothing about it (a point at 1e160 m made a spherical joint "3 rows of rank 0": a
/// body falling freely, its joint never enforced); before, the start is a false singular one.
inline constexpr double kJointArmLimit = 1e5;

template <typename S>
void ModelTpl<S>::check_joint_data(const ConstraintRowsTpl<S>& rows) const {
  using std::abs;
  for (int row = 0; row < rows.jacobian.rows(); ++row) {
    const Eigen::Index r = row;
    const int joint = constraints_->joint_of_row(row);
    bool finite = true;
    for (int k = 0; k < 2; ++k) {
      if (rows.jacobian.slot(row, k).body >= 0)
        finite = finite && rows.jacobian.values(row, k).allFinite();
    }
    if (!finite || !(rows.phi(r) == rows.phi(r)) ||
        !(abs(rows.phi(r)) < std::numeric_limits<S>::infinity()) ||
        !(abs(rows.phi_t(r)) < std::numeric_limits<S>::infinity())) {
      throw JointDataError(joint, 0,
                           "joint '" + constraints_->joint_name(joint) +
                               "': its constraint rows are not finite at the initial "
                               "configuration (inf or NaN): its points, axes or length overflow "
                               "double precision");
    }
    if (!constraints_->is_length_row(row)) continue;
    const std::array<int, 2> ends = constraints_->row_bodies(row);
    for (std::size_t k = 0; k < ends.size(); ++k) {
      if (!distinct_body(ends, k)) continue;
      const Body& body = bodies_[static_cast<std::size_t>(ends[k])];
      if (!body.is_free()) continue;
      // In double (the check runs on the double model, whose rows the others keep): the arm
      // without overflowing its square, ρ² = λ_min(I_Br)/m.
      const double arm =
          rows.jacobian.values(row, rows.jacobian.slot(row, 0).body == ends[k] ? 0 : 1)
              .template segment<3>(3)
              .template cast<double>()
              .stableNorm();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(
          body.I_Br_B().template cast<double>(), Eigen::EigenvaluesOnly);
      const double rho = std::sqrt(eigen.eigenvalues()(0) / static_cast<double>(body.mass()));
      if (!(arm <= kJointArmLimit * rho)) {
        std::ostringstream out;
        out.precision(3);
        out << "joint '" << constraints_->joint_name(joint) << "': its point on body '"
            << body.name() << "' is " << arm << " m from the body's reference point, " << arm / rho
            << " times the body's smallest radius of gyration " << rho
            << " m: beyond what double precision resolves beside the body's own size ("
            << kJointArmLimit
            << " radii: the body's translation no longer enters the joint's rows beside its "
               "rotation); give the point in the body's frame near the body";
        throw JointDataError(joint, ends[k] == ends[0] ? 0 : 1, out.str());
      }
    }
  }
}

template <typename S>
void ModelTpl<S>::check_projection_reached(const State& state, Workspace& ws, double tolerance,
                                           bool velocities) const {
  using std::abs;
  pose_bodies(state, ws);
  ConstraintSolveTpl<S>& s = ws.constraint;
  constraints_->evaluate(S(0), ws.kinematics, layout_, s.rows);
  const RelativeJointViolationTpl<S> after = relative_violation(s, state);
  if (after.position <= S(tolerance) && (!velocities || after.velocity <= S(tolerance))) return;
  // Each joint's largest residual, position level (m, or the sine of an angle).
  std::ostringstream out;
  out.precision(3);
  const int worst = constraints_->joint_of_row(after.position > S(tolerance) ? after.position_row
                                                                             : after.velocity_row);
  out << "joint '" << constraints_->joint_name(worst)
      << "' is not reached by the projection of the initial state onto the joints, which cannot "
         "reach them all; each joint's residual after projecting: ";
  for (int j = 0; j < constraints_->joint_count(); ++j) {
    const std::array<int, 2> rows = constraints_->joint_rows(j);
    S largest = S(0);
    bool length = true;
    for (int r = rows[0]; r < rows[0] + rows[1]; ++r) {
      if (abs(s.rows.phi(r)) > largest) {
        largest = abs(s.rows.phi(r));
        length = constraints_->is_length_row(r);
      }
    }
    out << (j > 0 ? ", " : "") << "joint '" << constraints_->joint_name(j) << "' "
        << static_cast<double>(largest) << (length ? " m" : " (sine of an angle)");
  }
  out << " after projecting (largest relative violation "
      << static_cast<double>(std::max(after.position, after.velocity)) << ", accepted " << tolerance
      << "): the joints cannot all hold at once — check their points, axes and lengths";
  throw InconsistentInitialStateError(worst, out.str());
}

/// How far check_singular_start moves the mechanism from its initial configuration, relative to
/// the joints' length scale: far enough that a row dependent only at the initial pose becomes
/// independent by ~1e-4 (six orders above the rank tolerance kRedundantRowTolerance) and
/// violated by ~1e-8 at second order, near enough that the projection back onto the enforced rows
/// converges in a few Newton steps.
inline constexpr double kSingularStartStep = 1e-4;
/// A row set aside as redundant stays satisfied to round-off along a structural redundancy (its Φ
/// is a function of the enforced rows' Φ, ~1e-15 after their projection); a singular start
/// violates it by ~kSingularStartStep² = 1e-8 relative. 1e-11 lies three orders from each.
inline constexpr double kRedundantRowDrift = 1e-11;

template <typename S>
void ModelTpl<S>::check_singular_start(const State& state, Workspace& ws) const {
  using std::abs;
  using std::max;
  ConstraintSolveTpl<S>& s = ws.constraint;
  // The projection a small motion away keeps the reference of the rows' conditioning at the
  // initial configuration (kReselectPivotFall).
  ConstraintTracker tracker = default_tracker_;
  factor_constraints_at(S(0), state, tracker, ws);
  tracker.rows = s.active;
  tracker.selection_ratio = s.selection_ratio;
  const std::vector<int> active = s.active;
  const Matrix J0 = s.rows.jacobian.dense();
  const Eigen::Index n = layout_.size();
  // A motion the enforced rows allow: the drives' own motion v_p = −M⁻¹J_aᵀA⁻¹Φ_t (the smallest
  // in the mass metric), and a generic free one d = (I − M⁻¹J_aᵀA⁻¹J_a) M⁻¹ z, z pseudo-random
  // (a fixed seed: the same answer on every machine), both in null(J_a) but for the drives.
  Vector drive = Vector::Zero(n);
  constraint_correction<S>(s.rows.phi_t, s);
  drive = s.x;
  std::mt19937 random(20261128u);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  Vector z(n);
  for (Eigen::Index k = 0; k < n; ++k) z(k) = S(gaussian(random));
  Vector free(n);
  stacked_inverse_mass(z, free, ws);
  s.rows.jacobian.multiply(free, s.rate);
  constraint_correction<S>(s.rate, s);
  free += s.x;
  // Each motion's size: the largest displacement of a body point within ℓ of its Br per unit.
  const auto size = [&](const Vector& x) {
    S largest = S(0);
    for (int b = 0; b < num_bodies(); ++b) {
      const int o = layout_.offset(b);
      largest = max(largest, S(x.template segment<3>(o).norm() +
                               joint_length_scale_ * x.template segment<3>(o + 3).norm() +
                               x.segment(o + 6, layout_.width(b) - 6).norm()));
    }
    return largest;
  };
  const S step = S(kSingularStartStep) * joint_length_scale_;
  const S drive_size = size(drive);
  const S free_size = size(free);
  if (!(drive_size > S(0)) && !(free_size > S(0))) return;  // a structure: nothing moves
  const S tau = drive_size > S(0) ? S(step / drive_size) : S(0);
  Vector delta = tau * drive;
  if (free_size > S(0)) delta += (step / free_size) * free;
  State moved = state;
  apply_position_increment(delta, moved);
  apply_prescribed_motion(tau, moved);
  // Back onto the enforced rows at t = τ (the drives moved on with the motion).
  bool projected = true;
  try {
    factor_constraints_at(tau, moved, tracker, ws);
    project_positions<S>(
        [&] { factor_constraints_at(tau, moved, tracker, ws); },
        [&] {
          S worst = S(0);
          for (int row : s.active) {
            worst = max(worst, S(abs(s.rows.phi(row)) /
                                 (constraints_->is_length_row(row) ? joint_length_scale_ : S(1))));
          }
          return worst;
        },
        [&](const Vector& d) { apply_position_increment(d, moved); },
        S(8) * std::numeric_limits<S>::epsilon(), s);
  } catch (const SingularConfigurationError&) {
    projected = false;
  }
  pose_bodies(moved, ws);
  constraints_->evaluate(tau, ws.kinematics, layout_, s.rows);
  // The set-aside row that moved furthest from the enforced rows' span, or was violated most.
  const Matrix J_moved = s.rows.jacobian.dense();
  const Matrix Jt_active = [&] {
    Matrix J_a(static_cast<Eigen::Index>(active.size()), n);
    for (std::size_t i = 0; i < active.size(); ++i) {
      J_a.row(static_cast<Eigen::Index>(i)) = J_moved.row(active[i]);
    }
    return row_normalized_transpose<S>(J_a);
  }();
  const Eigen::ColPivHouseholderQR<Matrix> qr(Jt_active);
  int worst_row = -1;
  S worst_independence = S(0);
  S worst_drift = S(0);
  for (int row = 0; row < constraints_->row_count(); ++row) {
    if (std::find(active.begin(), active.end(), row) != active.end()) continue;
    const S norm = J_moved.row(row).norm();
    const Vector direction =
        norm > S(0) ? Vector(J_moved.row(row).transpose() / norm) : Vector(Vector::Zero(n));
    const S independence = (Jt_active * qr.solve(direction) - direction).norm();
    const S drift =
        abs(s.rows.phi(row)) / (constraints_->is_length_row(row) ? joint_length_scale_ : S(1));
    if (independence > S(kRedundantRowTolerance) || drift > S(kRedundantRowDrift)) {
      if (independence > worst_independence || drift > worst_drift) worst_row = row;
      worst_independence = max(worst_independence, independence);
      worst_drift = max(worst_drift, drift);
    }
  }
  if (worst_row < 0 && projected) return;
  if (worst_row < 0) worst_row = active.empty() ? 0 : active.front();
  const int joint = constraints_->joint_of_row(worst_row);
  const std::string& name = constraints_->joint_name(joint);
  // The joints whose rows it depends on at t = 0: J_rᵀ = J_aᵀ c, the rows with a share in c.
  std::string partners;
  {
    Matrix J_a(static_cast<Eigen::Index>(active.size()), n);
    for (std::size_t i = 0; i < active.size(); ++i) {
      J_a.row(static_cast<Eigen::Index>(i)) = J0.row(active[i]);
    }
    const Vector c =
        J_a.transpose().colPivHouseholderQr().solve(Vector(J0.row(worst_row).transpose()));
    const S largest = c.cwiseAbs().maxCoeff();
    std::vector<int> joints;
    for (std::size_t i = 0; i < active.size(); ++i) {
      const int j = constraints_->joint_of_row(active[i]);
      if (abs(c(static_cast<Eigen::Index>(i))) > S(1e-8) * largest && j != joint &&
          std::find(joints.begin(), joints.end(), j) == joints.end()) {
        joints.push_back(j);
      }
    }
    for (std::size_t i = 0; i < joints.size(); ++i) {
      partners += (i > 0 ? ", '" : "'") + constraints_->joint_name(joints[i]) + "'";
    }
  }
  std::ostringstream out;
  out.precision(3);
  out << "joint '" << name << "' starts at a singular configuration: at t = 0 its constraints "
      << "depend on the others" << (partners.empty() ? "" : " (joints " + partners + ")")
      << ", but a motion of " << kSingularStartStep << " of the joints' length scale away they "
      << (worst_independence > S(kRedundantRowTolerance) ? "are independent of them"
                                                         : "are no longer satisfied with them")
      << " (independence " << static_cast<double>(worst_independence) << ", violation "
      << static_cast<double>(worst_drift)
      << " relative): a dead centre or a tangency, not a redundant row, where the motion and the "
         "multipliers are not determined; start the mechanism away from it";
  throw SingularConfigurationError(name, 0.0, out.str());
}

template <typename S>
void ModelTpl<S>::assemble_initial_state(const ConstraintOptions& options) {
  State state = scene_initial_state();
  Workspace ws = make_workspace();
  pose_bodies(state, ws);
  ConstraintRowsTpl<S> rows;
  rows.resize_sparse(constraints_->row_count());
  constraints_->evaluate(S(0), ws.kinematics, layout_, rows);
  const bool chosen_here = options.independent_rows.empty();
  if (chosen_here) check_joint_data(rows);
  active_rows_ = chosen_here ? core::independent_rows<S>(rows.jacobian) : options.independent_rows;
  default_tracker_ = make_constraint_tracker();
  // The joints' length scale ℓ: the largest arm from a body's Br to a joint point.
  joint_length_scale_ = core::joint_length_scale<S>(*constraints_, layout_, rows.jacobian);
  ws = make_workspace();
  ws.constraint.rows = rows;
  const RelativeJointViolationTpl<S> before = relative_violation(ws.constraint, state);
  const auto refuse = [&](int row, const char* level, double value) {
    const int joint = constraints_->joint_of_row(row);
    throw InconsistentInitialStateError(
        joint, "the initial state violates joint '" + constraints_->joint_name(joint) + "' at " +
                   level + " level by " + std::to_string(value) +
                   " (relative), more than the accepted " +
                   std::to_string(options.initial_tolerance) +
                   "; correct the bodies' initial positions and velocities, or set "
                   "project_initial_state = true in [scene] to project them onto the joints");
  };
  if (!options.project_initial_state && before.position > S(options.initial_tolerance)) {
    refuse(before.position_row, "position", static_cast<double>(before.position));
  }
  InitialProjection projection;
  try {
    projection = project(S(0), state, ws);
  } catch (const SingularConfigurationError&) {
    // The Newton iteration met a configuration where the rows lose rank on its way: report what
    // it reached, joint by joint (check_projection_reached throws).
    if (chosen_here) check_projection_reached(state, ws, options.initial_tolerance, false);
    throw;
  }
  if (!options.project_initial_state && projection.velocity > options.initial_tolerance) {
    refuse(before.velocity_row, "velocity", projection.velocity);
  }
  if (chosen_here) {
    // Every row reached, the ones set aside included (the projection enforced only the
    // independent rows), and the set-aside rows redundant rather than a singular start. The
    // positions first: a singular start is told by moving from consistent positions, and its
    // set-aside rows' velocities (a drive the start cannot follow) are not reached either.
    check_projection_reached(state, ws, options.initial_tolerance, false);
    if (active_rows_.size() < static_cast<std::size_t>(constraints_->row_count())) {
      check_singular_start(state, ws);
    }
    check_projection_reached(state, ws, options.initial_tolerance, true);
  }
}

template <typename S>
typename ModelTpl<S>::ConsistentInitialState ModelTpl<S>::consistent_initial_state() const {
  ConsistentInitialState initial{scene_initial_state(), {}};
  if (!constraints_) return initial;
  // The projection the constructor checked, step for step: on a fresh workspace, from the
  // scene's state, on the rows chosen there.
  Workspace ws = make_workspace();
  initial.projection = project(S(0), initial.state, ws);
  return initial;
}

}  // namespace flexref::core
