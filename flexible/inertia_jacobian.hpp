#pragma once
/// \file inertia_jacobian.hpp
/// Analytic derivatives of one flexible body's inertial, elastic and damping residual
///
///     R(y, x) = M(θ, q_f) x − Qv(θ, ω̄, q_f, q̇_f) + [0; 0; K q_f + D q̇_f],   x = (a, α̅, q̈_f) fixed,
///
/// (Model::dynamics_residual without the loads; docs/design/model.md, "Equations of motion,
/// quasi-velocity form") with respect to the body's state in tangent coordinates
/// [π̄ (3), ω̄ (3), q_f (n), q̇_f (n)], where π̄ is a body-frame rotation, A → A exp(π̄̃):
/// δ(A z) = −A z̃ δπ̄ and δ(Aᵀ a) = (Aᵀa)~ δπ̄. R depends on neither the position nor the
/// velocity of Br. With b = Aᵀ a, z_R = α̅ × s_t + S q̈_f + W² s_t + 2 W S q̇_f (so that
/// R_R = m a + A z_R), W = ω̄̃, Y_ab = X_baᵀ + P_ab q_f, dJ_ab = X_ab + X_ba + (P_ab + P_ba) q_f
/// (∂J_ab/∂q_f, n-vectors), dC_ab = P_ba q̇_f (∂C_ab/∂q_f) and dC'_ab = X_ba + P_ab q_f
/// (∂C_ab/∂q̇_f), the coupled model's blocks are
///
///     ∂R_R/∂π̄ = −A z̃_R       ∂R_θ/∂π̄ = s̃_t b̃       ∂R_f/∂π̄ = Sᵀ b̃
///     ∂R_R/∂ω̄ = A [−(ω̄ × s_t)~ − W s̃_t − 2 (S q̇_f)~]
///     ∂R_θ/∂ω̄ = −(Ī_θθ ω̄)~ + W Ī_θθ + 2 (tr(C) I − C)
///     ∂R_f/∂ω̄_c = Σ_b ω̄_b Y_cb + Σ_a ω̄_a Y_ac − 2 ω̄_c Σ_a Y_aa − 2 G_c q̇_f
///     ∂R_R/∂q_f = A (α̅̃ + W²) S
///     ∂R_θ/∂q_f,j = −b̃ S_j + tr(dJ_j) α̅ − dJ_j α̅ − W dJ_j ω̄ + [(G_a q̈_f)_j]_a
///                   + 2 (tr(dC_j) ω̄ − dC_j ω̄)
///     ∂R_f/∂q_f = K + Σ_ab (W²)_ab P_ab − Σ_a α̅_a G_a
///     ∂R_R/∂q̇_f = 2 A W S    ∂R_θ/∂q̇_f,j = 2 (tr(dC'_j) ω̄ − dC'_j ω̄)    ∂R_f/∂q̇_f = D − 2 Σ_a ω̄_a
///     G_a
///
/// from s_t = s0 + S q_f, Ī_θθ = tr(J) I − J, Ī_θf = Ī_θf0 + [q_fᵀ G_a]_a, the Qv of
/// inertia_terms.hpp and ∂(W² v)/∂ω̄ = −(ω̄ × v)~ − W ṽ. (The W Ī_θθ ω̄ term of tr(dJ) vanishes:
/// W ω̄ = 0.) The LTE model evaluates the inertia at q_f = 0, q̇_f = 0 and drops M_rf x_f from
/// the rigid rows: the same blocks with P_ab q_f = 0, q̇_f = 0, no S q̈_f in z_R and no
/// Ī_θf q̈_f in R_θ, and only K, D in the q_f, q̇_f columns.
///
/// **Geometric stiffening** (flexible/geometric_stiffness.hpp; coupled model only): with
/// s_t, Ī_θθ and C of `terms` already including Δs, ΔĪ, ΔC, the blocks gain (σ = ΔS q̇_f,
/// σ'' = ΔS q̈_f, v = Σ m J̇_w q̇_f, z_c = q̇_f·Z_c q̇_f; EQ, EQ', EQ'' the 3×n matrices with rows
/// (E_c q_f)ᵀ, (E_c q̇_f)ᵀ, (E_c q̈_f)ᵀ; dΔJ_ab = −(F_ab + F_ba) q_f, dΔC_ab = −F_ab q̇_f,
/// dΔC'_ab = −F_ab q_f; docs/geometric_stiffening.md, GS-12):
///
///     ∂R_R/∂π̄ += −A (2 W σ + σ'' + v)~      ∂R_f/∂π̄ += −EQᵀ b̃
///     ∂R_R/∂ω̄ += −2 A σ̃                      ∂R_f/∂ω̄_c += −Σ_k ω̄_k (F_ck + F_kc) q_f + 2 ω̄_c Σ_k
///     F_kk q_f ∂R_R/∂q_f += −A [(α̅̃ + W²) EQ + EQ'' + 2 W EQ']       ∂R_R/∂q̇_f += −2 A [W EQ + EQ']
///     ∂R_θ/∂q_f,j += b̃ EQ_j + tr(dΔJ_j) α̅ − dΔJ_j α̅ − W dΔJ_j ω̄ − [(Z_c q̈_f)_j]_c
///                    + 2 (tr(dΔC_j) ω̄ − dΔC_j ω̄)
///     ∂R_θ/∂q̇_f,j += 2 (tr(dΔC'_j) ω̄ − dΔC'_j ω̄) − 2 [(Z_c q̇_f)_j]_c
///     ∂R_f/∂q_f += −Σ_c b_c E_c − Σ_c α̅_c Z_c − Σ_ab (W²)_ab F_ab
///
/// Cost: 12 extra n×n matrix–vector products (P_ab q̇_f, G_a q̈_f; none under LTE) and
/// 12 n×n matrix additions for ∂R_f/∂q_f, i.e. O(n²). Allocates nothing.
/// Tested against central differences of Model::dynamics_residual
/// (tests/flexible/inertia_jacobian_test.cpp).
#include <Eigen/Core>

#include "flexible/inertia_terms.hpp"
#include "flexible/modal_data.hpp"

namespace flexref::flexible {

/// Tangent columns of the state: π̄, ω̄, then q_f and q̇_f.
inline constexpr int kJacobianRotation = 0;
inline constexpr int kJacobianAngularVelocity = 3;
inline constexpr int kJacobianModes = 6;

struct InertiaJacobianScratch {
  Eigen::Matrix<double, Eigen::Dynamic, 9> P_qd;   ///< column 3a+b: P_ab q̇_f
  Eigen::Matrix<double, Eigen::Dynamic, 3> G_qdd;  ///< column a: G_a q̈_f
  Eigen::Matrix<double, Eigen::Dynamic, 9> dJ;     ///< column 3a+b: dJ_ab (symmetric pairs)
  Eigen::Matrix<double, Eigen::Dynamic, 9> dC;     ///< column 3a+b: dC_ab or dC'_ab
  // Geometric stiffening's extra products.
  Eigen::Matrix<double, Eigen::Dynamic, 9> F_qd;   ///< column 3a+b: F_ab q̇_f
  Eigen::Matrix<double, Eigen::Dynamic, 3> E_qdd;  ///< column c: E_c q̈_f
  Eigen::Matrix<double, Eigen::Dynamic, 3> Z_qdd;  ///< column c: Z_c q̈_f
};

InertiaJacobianScratch make_inertia_jacobian_scratch(int mode_count);

/// Writes ∂R/∂[π̄, ω̄, q_f, q̇_f] ((6+n)×(6+2n)) into `out`, at the state of `terms` (products
/// and assembly at R_WB, ω̄, q_f, q̇_f: the LTE model's at q_f = q̇_f = 0) and the accelerations
/// x = (a_WBr, α̅, q̈_f). `coupled` selects the model. K and D are the modal stiffness and
/// damping diagonals. Throws std::invalid_argument on sizes.
void inertia_residual_jacobian(const ModalInvariants& invariants, const InertiaTerms& terms,
                               bool coupled, const Eigen::Ref<const Eigen::VectorXd>& q_f,
                               const Eigen::Vector3d& w_B,
                               const Eigen::Ref<const Eigen::VectorXd>& qd_f,
                               const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::VectorXd& K,
                               const Eigen::VectorXd& D, InertiaJacobianScratch& scratch,
                               Eigen::Ref<Eigen::MatrixXd> out);

}  // namespace flexref::flexible
