#pragma once
/// \file flexible_dynamics.hpp
/// Mass matrix, quadratic-velocity vector and kinetic energy of ONE flexible body in the
/// quasi-velocity form of docs/design/model.md ("Equations of motion, quasi-velocity form"), with
/// generalized velocities v = (Ṙ, ω̄, q̇_f) (global, body frame, modal):
///
///     M = [ m I        −A s̃_t     A S   ]
///         [ s̃_t Aᵀ     Ī_θθ       Ī_θf  ]
///         [ Sᵀ Aᵀ      Ī_θfᵀ      m_ff  ]
///
///     Qv_R = −A [ ω̄̃ ω̄̃ s_t + 2 ω̄̃ S q̇_f ]
///     Qv_θ = −ω̄̃ Ī_θθ ω̄ − 2 Σ m_k ũ_k ω̄̃ Φ_k q̇_f
///     Qv_f = −Σ m_k Φ_kᵀ [ ω̄̃ ω̄̃ ū_k + 2 ω̄̃ Φ_k q̇_f ]
///
/// Both follow from ṙ_k = L_k v with L_k = [I, −A ũ_k, A Φ_k] (eq. 14) and
/// Σ m_k δr_kᵀ r̈_k = δᵀ (M v̇ − Qv) (eq. 17): M = Σ m_k L_kᵀ L_k and
/// Qv = −Σ m_k L_kᵀ A [ω̄̃ω̄̃ ū_k + 2 ω̄̃ Φ_k q̇_f]. The signs above were checked against these
/// nodal definitions (tests/flexible/flexible_dynamics_test.cpp); none was found wrong.
///
/// The invariant-based evaluations cost O(n²); the `_by_nodes` versions are the O(N n²) direct
/// nodal sums they are tested against. The Σ terms reduce to the invariants of
/// flexible/modal_data.hpp (W = ω̄̃, X_ab = x_phi row 3a+b, P_ab = phi_phi[3a+b],
/// G_a = phi_cross_phi[a]):
///
///     Σ m Φᵀ ω̄̃ Φ       = −Σ_a ω̄_a G_a
///     Σ m Φᵀ ω̄̃ω̄̃ ū     = Σ_ab (W²)_ab (X_baᵀ + P_ab q_f)
///     Σ m ũ ω̄̃ Φ q̇_f    = tr(C) ω̄ − C ω̄,   C_ab = Σ m (Φ_k q̇_f)_a ū_k,b = X_ba q̇_f + q_fᵀ P_ba q̇_f
///     Σ m ũ ω̄̃ω̄̃ ū      = ω̄̃ Ī_θθ ω̄
///
/// flexible_mass_matrix and flexible_quadratic_velocity are the whole-matrix views of the
/// evaluation in flexible/inertia_terms.hpp (which the Model uses, allocation-free, with the
/// structured solve of flexible/mass_matrix_solve.hpp); they allocate that scratch per call
/// and are meant for tests and one-off evaluations.
#include <Eigen/Core>

#include "flexible/modal_data.hpp"

namespace flexref::flexible {

/// Note: M is positive definite only if the nodes have inertia about every axis. Point masses
/// on one straight line (the built-in beam: rotary inertia neglected) give a singular M (the
/// spin about the beam's axis; with equal bending shapes in both planes also when deformed);
/// such a body needs a rigid part or rotary inertia before M can be factored.
///
/// Writes the (6+n)×(6+n) mass matrix into M, which must already have that size (throws
/// std::invalid_argument otherwise, and on a q_f of the wrong size). Exactly symmetric.
void flexible_mass_matrix(const ModalInvariants& invariants, const Eigen::Matrix3d& R_WB,
                          const Eigen::VectorXd& q_f, Eigen::MatrixXd& M);

/// Writes Qv (6+n) into Qv, which must already have that size. w_B = ω̄ (body frame),
/// qd_f = q̇_f.
void flexible_quadratic_velocity(const ModalInvariants& invariants, const Eigen::Matrix3d& R_WB,
                                 const Eigen::VectorXd& q_f, const Eigen::Vector3d& w_B,
                                 const Eigen::VectorXd& qd_f, Eigen::VectorXd& Qv);

/// T = ½ vᵀ M v with v = (Ṙ = v_W, ω̄ = w_B, q̇_f), evaluated from the blocks (O(n²), no
/// allocation, M not formed).
double flexible_kinetic_energy(const ModalInvariants& invariants, const Eigen::Matrix3d& R_WB,
                               const Eigen::VectorXd& q_f, const Eigen::Vector3d& v_W,
                               const Eigen::Vector3d& w_B, const Eigen::VectorXd& qd_f);

/// M = Σ_k m_k L_kᵀ L_k with L_k = [I, −A ũ_k, A Φ_k] (direct nodal sum; M must be sized).
void flexible_mass_matrix_by_nodes(const ModalData& data, const Eigen::Matrix3d& R_WB,
                                   const Eigen::VectorXd& q_f, Eigen::MatrixXd& M);

/// Qv = −Σ_k m_k L_kᵀ A [ω̄̃ ω̄̃ ū_k + 2 ω̄̃ Φ_k q̇_f] (direct nodal sum; Qv must be sized).
void flexible_quadratic_velocity_by_nodes(const ModalData& data, const Eigen::Matrix3d& R_WB,
                                          const Eigen::VectorXd& q_f, const Eigen::Vector3d& w_B,
                                          const Eigen::VectorXd& qd_f, Eigen::VectorXd& Qv);

/// T = ½ Σ_k m_k |ṙ_k|², ṙ_k = Ṙ + A (ω̄ × ū_k) + A Φ_k q̇_f (eq. 14).
double flexible_kinetic_energy_by_nodes(const ModalData& data, const Eigen::Matrix3d& R_WB,
                                        const Eigen::VectorXd& q_f, const Eigen::Vector3d& v_W,
                                        const Eigen::Vector3d& w_B, const Eigen::VectorXd& qd_f);

}  // namespace flexref::flexible
