#pragma once
/// \file inertia_terms.hpp
/// The state-dependent inertia terms of one flexible body — the mass-matrix blocks and Qv of
/// flexible_dynamics.hpp (docs/design/model.md, "Equations of motion, quasi-velocity form") —
/// evaluated in two stages so that every n×n invariant is read once per evaluation:
///
/// 1. modal products (compute_modal_products, the only O(n²) work: 12 matrix–vector products,
///    each on its matrix's nonzero rows and columns — compressed_block_tpl.hpp)
///
///        u_ab = P_ab q_f   (nine n-vectors, column 3a+b of P_q; P_ba = P_abᵀ),
///        g_a  = G_a q̇_f    (three n-vectors, column a of G_qd),
///        X q_f, X q̇_f      (X: the 9×n x_phi, row 3a+b = X_ab),   S q_f, S q̇_f;
///
/// 2. assembly (assemble_inertia_terms, O(n), allocation-free), from those products only:
///
///        s_t   = s0 + S q_f
///        Ī_θθ  = tr(J) I − J,   J = J0 + L + Lᵀ + Q,   L_ab = (X q_f)_{3a+b},  Q_ab = q_f · u_ab
///        Ī_θf  = Ī_θf0 + [(u_cb − u_bc)ᵀ]_(row a)        ((a,b,c) cyclic: q_fᵀ G_a = (G_aᵀ q_f)ᵀ
///                                                         and G_aᵀ = P_cb − P_bc)
///        C_ab  = (X q̇_f)_{3b+a} + q̇_f · u_ab           (qᵀ P_ba q̇ = (P_baᵀ q)·q̇ = u_ab·q̇)
///        Qv_R  = −A [ W² s_t + 2 W S q̇_f ]
///        Qv_θ  = −W Ī_θθ ω̄ − 2 (tr(C) ω̄ − C ω̄)
///        Qv_f  = −Σ_ab (W²)_ab (X_baᵀ + u_ab) + 2 Σ_a ω̄_a g_a      (W = ω̄̃; W² symmetric)
///
/// The mass-matrix blocks are M_rr = [m I, −A s̃_t; s̃_t Aᵀ, Ī_θθ] (6×6), M_rf = [A S; Ī_θf]
/// (6×n) and the constant m_ff. The old evaluation formed Q_ab and C_ab as bilinear forms and
/// Qv_f by nine matrix–vector products of its own (36 n² multiply-adds); the products above
/// serve all of them (12 n²). The assembly alone depends on R_WB and ω̄, so a derivative with
/// respect to the rigid state reuses the products.
///
/// **Geometric stiffening** (flexible/geometric_stiffness.hpp, when the invariants carry it):
/// stage 1 adds the products F_ab q_f, E_c q_f, E_c q̇_f, Z_c q_f, Z_c q̇_f; stage 2 replaces
/// s_t, S q̇_f, J, C and Ī_θf by s_t + Δs, S q̇_f + ΔS q̇_f, J + ΔJ, C + ΔC, Ī_θf + ΔĪ_θf and adds
/// (docs/geometric_stiffening.md, GS-9 … GS-11)
///
///        M_rf  += [A ΔS; ΔĪ_θf],   ΔS row c = −(E_c q_f)ᵀ,  ΔĪ_θf row c = −(Z_c q_f)ᵀ
///        Qv_R  += −A Σ_k m_k J̇_w,k q̇_f           (GS-6; the rest through s_t and S q̇_f)
///        Qv_θ  += z,  z_c = q̇_f·Z_c q̇_f         (GS-7; the rest through J and C)
///        Qv_f  += Σ_ab (W²)_ab F_ab q_f          (the centrifugal geometric stiffness)
#include <Eigen/Core>

#include "flexible/geometric_stiffness.hpp"
#include "flexible/inertia_terms_tpl.hpp"
#include "flexible/modal_data.hpp"

namespace flexref::flexible {

/// Scratch and results of one flexible body's inertia terms in double (InertiaTermsTpl,
/// flexible/inertia_terms_tpl.hpp, for any scalar), sized once for n modes
/// (make_inertia_terms); neither stage reallocates.
using InertiaTerms = InertiaTermsTpl<double>;

/// Terms sized for n modes, all zero.
InertiaTerms make_inertia_terms(int mode_count);

/// Stage 1 at (q_f, q̇_f): O(n²), allocates nothing. Throws std::invalid_argument on sizes.
void compute_modal_products(const ModalInvariants& invariants,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& terms);

/// Stage 1 at q_f = 0, q̇_f = 0 (the LTE model's inertia terms): every product is zero, O(n).
void set_undeformed_products(InertiaTerms& terms);

/// Stage 2 from the products of the same (q_f, q̇_f): M_rr, M_rf, Qv at attitude R_WB and
/// angular velocity w_B = ω̄. O(n), allocates nothing. Throws std::invalid_argument on sizes.
void assemble_inertia_terms(const ModalInvariants& invariants, const Eigen::Matrix3d& R_WB,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Vector3d& w_B,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& terms);

/// Both stages.
void evaluate_inertia_terms(const ModalInvariants& invariants, const Eigen::Matrix3d& R_WB,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Vector3d& w_B,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& terms);

}  // namespace flexref::flexible
