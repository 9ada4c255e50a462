#pragma once
/// \file ideal_joints.hpp
/// The constraint rows of a scene's ideal joints in scalar type S (core::ConstraintEquationsTpl):
/// double for core::Model, long double and float128 for the extended and quad references.
/// Definitions in ideal_joints_impl.hpp; double is instantiated in ideal_joints.cpp, the others
/// in precision/.
///
/// Rows (docs/joints.md, "Ideal joints"; a the first end, b the second, X, Y, Z the world axes of
/// an end's joint frame, d = p_a − p_b, every vector in the world frame):
// clang-format off
///   point     Φ = p_a − p_b                          (3 rows, m)
///   slide     Φ = u_b · d,  u_b ∈ {X_b, Y_b}          (m)
///             Φ = Z_b · d − s(t)                      (driven prismatic, m)
///   rotation  Φ = p · q, p on one end, q on the other (the sine of the angle error):
///             Z_b·X_a, Z_b·Y_a                        (axes parallel)
///             X_b·Y_a                                 (no twist)
///             Z_b·Z_a                                 (universal)
///             X_a · (cos φ(t) Y_b − sin φ(t) X_b)     (driven revolute: sin(ψ − φ(t)), ψ the
///                                                      angle of X_a from X_b about Z_b)
///   distance  Φ = (|d|² − L²)/(2L)                   (m near the manifold; λ in N)
// clang-format on
/// with Φ̇ = J v + Φ_t and Φ̈ = J v̇ − γ derived in ideal_joints_impl.hpp row by row. A point
/// P of body B moves with v_P = v_Br + ω × r + A Φ_P q̇_f (r = A (x_P − p_BoBr + Φ_P q_f),
/// ω = A ω̄), so ∂(u·v_P)/∂(v_Br, ω̄, q̇_f) = (uᵀ, (Aᵀ (r × u))ᵀ, uᵀ A Φ_P); a vector fixed in B
/// turns with ω, so ∂(c·ω)/∂ω̄ = (Aᵀ c)ᵀ. At a node of a flexible body the joint's axes turn
/// with the body frame: the modal data carry no nodal rotations (docs/joints.md says when
/// that is exact).
#include <span>
#include <string>
#include <vector>

#include "constraint/ideal_joint.hpp"
#include "core/constraint_equations.hpp"

namespace flexref::constraint {

template <typename S>
class IdealJointsTpl final : public core::ConstraintEquationsTpl<S> {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Kinematics = core::BodyKinematicsTpl<S>;

  /// The joints of a model with `body_count` bodies. Throws std::invalid_argument for an end on
  /// an unknown body, a first end on the ground, both ends on one body, a non-positive distance,
  /// a drive on a joint that is neither revolute nor prismatic, or a node end without Φ_k.
  IdealJointsTpl(std::vector<IdealJointSpec> joints, int body_count);

  const std::vector<IdealJointSpec>& joints() const { return specs_; }

  int row_count() const override { return static_cast<int>(row_joint_.size()); }
  std::array<int, 2> row_bodies(int row) const override;
  int joint_count() const override { return static_cast<int>(specs_.size()); }
  int joint_of_row(int row) const override { return row_joint_[static_cast<std::size_t>(row)]; }
  const std::string& joint_name(int joint) const override {
    return specs_[static_cast<std::size_t>(joint)].name;
  }
  std::array<int, 2> joint_rows(int joint) const override {
    return {first_row_[static_cast<std::size_t>(joint)],
            core_row_count(static_cast<std::size_t>(joint))};
  }
  bool is_length_row(int row) const override { return length_row_[static_cast<std::size_t>(row)]; }
  bool blocks_read_own_end(int row) const override {
    return point_row_[static_cast<std::size_t>(row)];
  }
  void evaluate(const S& t, std::span<const Kinematics> bodies, const core::VelocityLayout& layout,
                core::ConstraintRowsTpl<S>& rows) const override;
  /// evaluate on the rows r with wanted[r] ≠ 0 alone (row_count() entries), each by the same
  /// arithmetic as evaluate's, so to the same bits; a joint none of whose rows is wanted is
  /// skipped whole. The other rows' J blocks and Φ_t are zero, their Φ and γ left as they were:
  /// for a caller that enforces a few of many rows (the reduced form's closures,
  /// constraint/reduced_model.hpp) and reads no other.
  void evaluate_rows(const S& t, std::span<const Kinematics> bodies,
                     const core::VelocityLayout& layout, std::span<const char> wanted,
                     core::ConstraintRowsTpl<S>& rows) const;
  void evaluate_rates(const S& t, std::span<const Kinematics> bodies,
                      const core::VelocityLayout& layout,
                      core::ConstraintRowsTpl<S>& rows) const override;
  core::JointReactionTpl<S> reaction(int joint, std::span<const Kinematics> bodies,
                                     const core::VelocityLayout& layout,
                                     const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>&
                                         generalized_force) const override;
  bool driven(int joint) const override {
    return specs_[static_cast<std::size_t>(joint)].drive.active;
  }
  std::string describe(int joint, std::span<const core::Body> bodies) const override;
  void append_discontinuities(std::vector<double>& times) const override;

  /// One end's data in S.
  struct End {
    int body = kGround;
    Vector3 x_P = Vector3::Zero();            ///< from Bo, body frame (ground: world point)
    Eigen::Matrix<S, 3, Eigen::Dynamic> phi;  ///< Φ_k (node ends), else empty
    Matrix3 R_BJ = Matrix3::Identity();
  };

 private:
  int core_row_count(std::size_t joint) const { return first_row_[joint + 1] - first_row_[joint]; }
  /// evaluate's body on the rows r with wanted(r) true, γ only with kGamma.
  template <bool kGamma, typename Wanted>
  void evaluate_where(const S& t, std::span<const Kinematics> bodies,
                      const core::VelocityLayout& layout, core::ConstraintRowsTpl<S>& rows,
                      const Wanted& wanted) const;

  std::vector<IdealJointSpec> specs_;
  std::vector<End> a_;
  std::vector<End> b_;
  std::vector<S> length_;
  std::vector<int> first_row_;  ///< per joint, and one past the last
  std::vector<int> row_joint_;
  std::vector<bool> length_row_;
  /// The point rows (detail::point_rows in evaluate): each J block reads its own end alone.
  std::vector<bool> point_row_;
};

using IdealJoints = IdealJointsTpl<double>;

extern template class IdealJointsTpl<double>;

}  // namespace flexref::constraint
