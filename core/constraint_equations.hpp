#pragma once
/// \file constraint_equations.hpp
/// The interface of holonomic constraints between bodies — ideal joints (constraint/) — as the
/// model sees them, in scalar type S (the force elements' pattern: the interface here, the
/// equations in their own folder). docs/design/model.md, "Ideal joints":
///
///   M v̇ + Jᵀ λ = Qe + Qv − [0; 0; K q_f + D q̇_f],   Φ(q, t) = 0,
///   Φ̇ = J v + Φ_t = 0,   Φ̈ = J v̇ − γ = 0,
///
/// with v the stacked generalized velocities of the bodies, body b contributing
/// v_b = (v_WBr, ω̄, q̇_f) (6 + n_b entries, in that order: the accelerations x = (a_WBr, α̅, q̈_f)
/// the model solves for). A row of J acts on at most two bodies.
#include <Eigen/Core>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "core/constraint_jacobian_tpl.hpp"
#include "core/force_element.hpp"
#include "core/velocity_layout.hpp"

namespace flexref::core {

/// The constraint rows at one configuration and time, in S.
template <typename S>
struct ConstraintRowsTpl {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  /// m × N: ∂Φ̇/∂v by its body blocks (core/constraint_jacobian_tpl.hpp), always filled; its
  /// pattern is built at the first evaluation unless the owner built it (allocation-free after).
  ConstraintJacobianTpl<S> jacobian;
  /// The same J dense, filled only where sized (resize(); resize_sparse() leaves it empty): for
  /// callers that read J entry by entry. Its cost is O(m N) per evaluation.
  Matrix J;
  Vector phi;    ///< Φ (m or rad per row: point and slide rows in m, rotation rows the sine of
                 ///< an angle, distance rows (|d|² − L²)/(2L) in m)
  Vector phi_t;  ///< Φ_t: Φ̇ = J v + Φ_t (driven rows; zero otherwise)
  Vector gamma;  ///< γ: Φ̈ = J v̇ − γ (everything of Φ̈ but J v̇, with its sign changed)

  /// Sized for `rows` rows, the dense J included.
  void resize(int rows, int velocities) {
    resize_sparse(rows);
    J = Matrix::Zero(rows, velocities);
  }
  /// Sized for `rows` rows, J by its blocks only.
  void resize_sparse(int rows) {
    J.resize(0, 0);
    phi = Vector::Zero(rows);
    phi_t = Vector::Zero(rows);
    gamma = Vector::Zero(rows);
  }
};

/// What one joint exerts on its first body at a state: the force (world) and the torque about
/// the joint's point on that body (world), from the multipliers of the joint's rows.
template <typename S>
struct JointReactionTpl {
  Eigen::Matrix<S, 3, 1> f_W = Eigen::Matrix<S, 3, 1>::Zero();
  Eigen::Matrix<S, 3, 1> tau_W = Eigen::Matrix<S, 3, 1>::Zero();
};

/// Holonomic constraints on the bodies of a model (Drake's constraint interface in spirit): rows
/// grouped by joint, each row acting on at most two bodies.
template <typename S>
class ConstraintEquationsTpl {
 public:
  using Kinematics = BodyKinematicsTpl<S>;

  virtual ~ConstraintEquationsTpl() = default;

  /// Number of rows m.
  virtual int row_count() const = 0;
  /// The bodies row r acts on (−1: none; ground ends have no columns).
  virtual std::array<int, 2> row_bodies(int row) const = 0;
  /// Number of joints, the joint that owns row r, and a joint's name (the prefix of its output
  /// columns) and its rows [first, first + count).
  virtual int joint_count() const = 0;
  virtual int joint_of_row(int row) const = 0;
  virtual const std::string& joint_name(int joint) const = 0;
  virtual std::array<int, 2> joint_rows(int joint) const = 0;
  /// True when row r is a position row in m (point, slide, distance), false for a rotation row
  /// (dimensionless: the sine of an angle).
  virtual bool is_length_row(int row) const = 0;
  /// True when row r's J block on each of its bodies reads that body's pose alone (a point row:
  /// Φ = (p_a − p_b)·u with u a world axis, J_b = ±(uᵀ, (Aᵀ(r × u))ᵀ, uᵀAΦ_P) from body b's own
  /// arm and attitude); false where a block reads the other end's pose too (a vector fixed in
  /// the other body, a slide along its axis, a distance's direction). For the sparsity of
  /// Jacobians that read J (reference/dae_coloured_jacobian.hpp).
  virtual bool blocks_read_own_end(int row) const = 0;
  /// Fills rows.phi, rows.jacobian (and rows.J where sized), rows.phi_t and rows.gamma at the
  /// bodies' poses and velocities (kinematics: A(θ), the state and the q_f the equations see).
  /// rows is sized by the caller (ConstraintRowsTpl::resize or resize_sparse); the entries of J
  /// outside the rows' bodies stay zero. Must not allocate once rows.jacobian has its pattern
  /// (prepare_rows).
  virtual void evaluate(const S& t, std::span<const Kinematics> bodies,
                        const VelocityLayout& layout, ConstraintRowsTpl<S>& rows) const = 0;
  /// evaluate without γ (rows.gamma left as it was): Φ, J and Φ_t to evaluate's bits, for a
  /// caller that reads the rows' positions and rates alone (the joint check,
  /// Model::relative_joint_violation). evaluate itself where not overridden.
  virtual void evaluate_rates(const S& t, std::span<const Kinematics> bodies,
                              const VelocityLayout& layout, ConstraintRowsTpl<S>& rows) const {
    evaluate(t, bodies, layout, rows);
  }
  /// The reaction of each joint on its first body from the stacked generalized constraint forces
  /// on the bodies, F = −Jᵀ λ restricted to the joint's rows (joint_forces: N entries per joint,
  /// only the joint's first body's block read).
  virtual JointReactionTpl<S> reaction(
      int joint, std::span<const Kinematics> bodies, const VelocityLayout& layout,
      const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& generalized_force) const = 0;
  /// True when the joint is driven (a rheonomic row: its reaction does work, W_drive).
  virtual bool driven(int joint) const {
    (void)joint;
    return false;
  }
  /// One line per joint for `flexref check`, naming its ends' bodies and nodes by their names in
  /// `bodies` (the model's; core/element_text.hpp).
  virtual std::string describe(int joint, std::span<const Body> bodies) const = 0;
  /// Builds rows.jacobian's pattern on `layout` (the rows' bodies) unless it has it. Allocates
  /// only then.
  void prepare_rows(const VelocityLayout& layout, ConstraintRowsTpl<S>& rows) const {
    if (rows.jacobian.rows() == row_count() && rows.jacobian.cols() == layout.size()) return;
    rows.jacobian.build(row_count(), layout, [&](int r) { return row_bodies(r); });
  }
  /// Known times where a drive law's derivatives jump.
  virtual void append_discontinuities(std::vector<double>& times) const { (void)times; }
};

using ConstraintEquations = ConstraintEquationsTpl<double>;
using JointReaction = JointReactionTpl<double>;
using ConstraintRows = ConstraintRowsTpl<double>;

}  // namespace flexref::core
