#pragma once
/// \file mass_matrix_solve.hpp
/// Structured solves with one flexible body's mass matrix (docs/design/model.md, "Equations of
/// motion, quasi-velocity form", "Known rows", "The LTE model"), in O(n²) per evaluation:
///
///     M = [ M_rr   M_rf ]     M_rr (6×6) and M_rf (6×n) from inertia_terms.hpp,
///         [ M_rfᵀ  m_ff ]     m_ff constant, factored once: m_ff = L Lᵀ (ModalMassFactor).
///
/// **Coupled.** Rows 0..k−1 are known (k = 0 free, 3 pivot: R̈ = 0, 6 prescribed: R̈ = 0 and
/// the law's α̅), u = k..5 are the unknown rigid rows. With B̂ᵀ = L⁻¹ M_ufᵀ (n×r, r = 6 − k) and
/// b̂ = L⁻¹ (b_f − M_kfᵀ x_k), the unknown rows follow from the r×r Schur complement of m_ff:
///
///     Σ   = M_uu − B̂ B̂ᵀ                           (SPD when M is)
///     x_u = Σ⁻¹ (b_u − M_uk x_k − B̂ b̂)
///     x_f = L⁻ᵀ (b̂ − B̂ᵀ x_u)
///
/// This is the Cholesky factorization of M with the rows permuted to (f, u) — [L 0; B̂ L_Σ] —
/// whose m_ff block never changes: per evaluation r forward substitutions with L for B̂ᵀ (the
/// translational columns L⁻¹ Sᵀ Aᵀ use the constant L⁻¹ Sᵀ, so at most 3), one for b̂ and one
/// backward one, i.e. ≤ 2.5 n² multiply-adds, against (6+n)³/3 for a dense Cholesky of M.
/// Cholesky is backward stable under symmetric permutations, so the result agrees with the
/// dense factorization to rounding (tests/flexible/mass_matrix_solve_test.cpp).
///
/// **LTE** (block lower triangular: the rigid rows without M_rf): x_u = M_uu⁻¹ (b_u − M_uk x_k),
/// then the modal rows.
///
/// **Modal rows** (LTE, and the hybrid schemes' modal step): x_f = m_ff⁻¹ (b_f − M_rfᵀ x_r) with
/// all six rigid accelerations x_r given: n² multiply-adds.
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "flexible/inertia_terms.hpp"
#include "flexible/mass_matrix_solve_tpl.hpp"
#include "flexible/modal_data.hpp"

namespace flexref::flexible {

/// The constant part, the Cholesky factor of m_ff and L⁻¹ Sᵀ (n×3), built once per body, and
/// the scratch of the structured solves, sized once for n modes (make_mass_solve_scratch): in
/// double (flexible/mass_matrix_solve_tpl.hpp defines them, and the solves, for any scalar).
using ModalMassFactor = ModalMassFactorTpl<double>;
using MassSolveScratch = MassSolveScratchTpl<double>;

MassSolveScratch make_mass_solve_scratch(int mode_count);

/// The coupled system M x = b for the rows [known, 6+n): x's first `known` entries (0, 3 or 6)
/// are given, the others are written. Uses terms.M_rr, terms.M_rf. O(n²), allocates nothing.
/// When the Schur complement is not positive definite (M singular: a body without inertia
/// about some axis) the unknown entries are NaN. Throws std::invalid_argument on sizes.
void solve_coupled(const ModalMassFactor& factor, const InertiaTerms& terms, int known,
                   const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& scratch,
                   Eigen::Ref<Eigen::VectorXd> x);
/// solve_coupled in two parts, for many right-hand sides at one state (a Jacobian): the
/// factorization (B̂ᵀ and Σ's Cholesky factor, ≤ 1.5 n² + O(n)) and its application to one
/// right-hand side (n² + O(n)), which uses the `known` of the last factorization.
void factor_coupled(const ModalMassFactor& factor, const InertiaTerms& terms, int known,
                    MassSolveScratch& scratch);
void apply_coupled(const ModalMassFactor& factor, const InertiaTerms& terms,
                   const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& scratch,
                   Eigen::Ref<Eigen::VectorXd> x);

/// The LTE system (rigid rows without M_rf, modal rows with it). Same contract, and the same
/// split into a factorization (the Cholesky factor of M_uu) and its application.
void solve_lte(const ModalMassFactor& factor, const InertiaTerms& terms, int known,
               const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& scratch,
               Eigen::Ref<Eigen::VectorXd> x);
void factor_lte(const InertiaTerms& terms, int known, MassSolveScratch& scratch);
void apply_lte(const ModalMassFactor& factor, const InertiaTerms& terms,
               const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& scratch,
               Eigen::Ref<Eigen::VectorXd> x);

/// The modal rows: x.tail(n) = m_ff⁻¹ (b_f − M_rfᵀ x.head(6)), x.head(6) given.
void solve_modal_rows(const ModalMassFactor& factor, const InertiaTerms& terms,
                      const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& scratch,
                      Eigen::Ref<Eigen::VectorXd> x);

}  // namespace flexref::flexible
