#pragma once
/// \file newton_matrix.hpp
/// Solves with the Newton matrix of an implicit method on the ODE form (reference/ode_form.hpp),
/// A = I − γ J with J = ∂f/∂y (reference/structured_jacobian.hpp), by eliminating the positions:
/// y splits into positions P (p, θ, q_f of every body), velocities V (v, ω̄, q̇_f) and the
/// the integrals W (W_d, then the applied and drives' work and the wear work: ode_form.hpp), and
/// the kinematic rows make A_PP and A_PV block diagonal:
///
///     A_PP = I except the 4×4 blocks I − (γ/2) [0 −ω̄ᵀ; ω̄ −ω̄̃] of θ,
///     A_PV: −γ I from p to v and from q_f to q̇_f, −(γ/2) Ḡ(θ)ᵀ from θ to ω̄ (4×3),
///     A(:, W) = e_W for each integral's column (nothing depends on an integral).
///
/// So A x = b reduces to the velocities:
///
///     S x_V = b_V − A_VP A_PP⁻¹ b_P,   S = A_VV − A_VP A_PP⁻¹ A_PV     (dim V = Σ (6 + n))
///     x_P = A_PP⁻¹ (b_P − A_PV x_V),   x_W = (b_W − A_WP x_P − A_WV x_V) / A_WW per integral,
///
/// with S factored by LU with partial pivoting: (6 + n)³ against (13 + 2n + 1)³ for the dense
/// LU of A (≈ 8× fewer operations for a 64-mode body), and a solve of O((6 + n)²). This is
/// Gaussian elimination with the pivots of the P block taken first, which are 1 (or the
/// well-conditioned 4×4 θ blocks, |det − 1| = O(γ|ω̄|)), so it is as stable as the dense LU
/// for the step sizes where A is well conditioned. The values are A's own (as a solver forms it
/// from J), read in place; only the pattern is assumed, and factor() checks it.
#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

#include "reference/ode_form.hpp"

namespace flexref::reference {

class NewtonMatrixSolver {
 public:
  explicit NewtonMatrixSolver(const OdeForm& form);

  int size() const { return size_; }
  /// Dimension of the reduced (velocity) system.
  int reduced_size() const { return static_cast<int>(velocity_.size()); }

  /// Factors A, column-major with leading dimension ld ≥ size(). Returns false when A lacks
  /// the pattern above (a non-zero entry where the kinematic rows have none) or S is singular;
  /// allocates nothing.
  bool factor(const double* A, int ld);
  /// x ← A⁻¹ x for the last factored A (x has size() entries); allocates nothing.
  void solve(double* x) const;

 private:
  struct ThetaBlock {
    int theta = 0;                                                        ///< θ's offset in y
    int w = 0;                                                            ///< ω̄'s offset in y
    int w_reduced = 0;                                                    ///< ω̄'s index in V
    Eigen::Matrix4d T_inverse = Eigen::Matrix4d::Identity();              ///< A(θ, θ)⁻¹
    Eigen::Matrix<double, 4, 3> C = Eigen::Matrix<double, 4, 3>::Zero();  ///< A(θ, ω̄)
  };
  /// A position whose A_PP block is 1 and whose A_PV entry is c on its velocity.
  struct ScalarPair {
    int position = 0;          ///< in y
    int velocity = 0;          ///< in y
    int velocity_reduced = 0;  ///< in V
    double c = 0.0;
  };

  int size_ = 0;
  int work_ = -1;                  ///< the first integral's (W_d's) index in y, or −1
  int integrals_ = 0;              ///< the integrals' count, from work_
  std::vector<int> velocity_;      ///< V: indices in y
  std::vector<int> position_;      ///< P: indices in y
  std::vector<ScalarPair> pairs_;  ///< p ↔ v, q_f ↔ q̇_f
  std::vector<ThetaBlock> thetas_;
  std::vector<int> kind_;      ///< per y index: 0 position, 1 velocity, 2 work
  std::vector<int> reduced_;   ///< per y index: its index within P or V
  std::vector<int> partner_;   ///< per y index: the velocity of a p or q_f, or −1
  std::vector<int> theta_of_;  ///< per y index: its θ block in thetas_, or −1
  Eigen::MatrixXd A_VP;        ///< gathered A(V, P)
  Eigen::MatrixXd A_WP, A_WV;  ///< the integrals' rows (when tracked)
  Eigen::VectorXd A_WW;        ///< their diagonal
  Eigen::MatrixXd S;           ///< the reduced matrix
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  mutable Eigen::VectorXd z_P_, x_V_, rhs_V_;
};

}  // namespace flexref::reference
