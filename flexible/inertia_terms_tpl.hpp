#pragma once
/// \file inertia_terms_tpl.hpp
/// The two-stage evaluation of one flexible body's inertia terms (flexible/inertia_terms.hpp
/// gives the formulas) written once for any scalar type S: double (InertiaTerms, which every
/// integrator uses) and the extended and quad precisions of precision/.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "flexible/geometric_stiffness_tpl.hpp"
#include "flexible/modal_invariants_tpl.hpp"

namespace flexref::flexible {

/// Scratch and results of one flexible body's inertia terms, sized once for n modes
/// (make_inertia_terms); neither stage reallocates.
template <typename S>
struct InertiaTermsTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  // Stage 1: modal products.
  Eigen::Matrix<S, Eigen::Dynamic, 9> P_q;   ///< column 3a+b: u_ab = P_ab q_f (n×9)
  Eigen::Matrix<S, Eigen::Dynamic, 3> G_qd;  ///< column a: g_a = G_a q̇_f (n×3)
  Eigen::Matrix<S, 9, 1> X_q = Eigen::Matrix<S, 9, 1>::Zero();   ///< X q_f
  Eigen::Matrix<S, 9, 1> X_qd = Eigen::Matrix<S, 9, 1>::Zero();  ///< X q̇_f
  Vector3 S_q = Vector3::Zero();                                 ///< S q_f
  Vector3 S_qd = Vector3::Zero();                                ///< S q̇_f
  BlockProductScratchTpl<S> block_scratch;     ///< the compressed products' gather (n)
  Eigen::Matrix<S, Eigen::Dynamic, 1> P_t_qd;  ///< P_bcᵀ q̇_f while forming g_a (n)

  // Stage 2: assembled terms (body frame unless the name says otherwise).
  Matrix3 R_WB = Matrix3::Identity();        ///< the attitude they were assembled at
  Vector3 s_t = Vector3::Zero();             ///< first moment about Br
  Matrix3 I_tt = Matrix3::Zero();            ///< Ī_θθ, exactly symmetric
  Matrix3 C = Matrix3::Zero();               ///< C_ab (Coriolis term of Qv_θ)
  Eigen::Matrix<S, 6, 6> M_rr;               ///< rigid block of M (exactly symmetric)
  Eigen::Matrix<S, 6, Eigen::Dynamic> M_rf;  ///< [A S; Ī_θf] (6×n)
  Eigen::Matrix<S, Eigen::Dynamic, 1> Qv;    ///< quadratic-velocity vector (6+n)

  // Geometric stiffening (unused, sized n×…, when the body has none).
  GeometricProductsTpl<S> geometric_products;  ///< stage 1
  ForeshorteningTermsTpl<S> foreshortening;  ///< stage 2: Δs, ΔS q̇, ΔJ, ΔC, … (included above)
  /// True when M_rf's translation rows are A S (no stiffening): the structured solve then uses
  /// the constant L⁻¹ Sᵀ (flexible/mass_matrix_solve.hpp).
  bool constant_translation_coupling = true;

  int mode_count() const { return static_cast<int>(P_q.rows()); }
};

namespace detail {

template <typename S>
Eigen::Matrix<S, 3, 3> hat_tpl(const Eigen::Matrix<S, 3, 1>& a) {
  Eigen::Matrix<S, 3, 3> m;
  m << S(0), -a(2), a(1), a(2), S(0), -a(0), -a(1), a(0), S(0);
  return m;
}

template <typename S>
void check_inertia_terms(const char* where, const ModalInvariantsTpl<S>& inv, Eigen::Index q_size,
                         Eigen::Index qd_size, const InertiaTermsTpl<S>& terms) {
  const Eigen::Index n = inv.mode_count;
  // The products read the compressed pair matrices, which modal_invariants_tpl builds with
  // phi_phi: invariants assembled by hand without them would give zero products.
  if (n > 0 && inv.phi_phi_blocks[0].dimension != n) {
    throw std::invalid_argument(std::string(where) +
                                ": the invariants' compressed pair matrices (phi_phi_blocks) "
                                "were not built for their " +
                                std::to_string(n) + " modes (modal_invariants_tpl builds them)");
  }
  if (q_size != n || qd_size != n || terms.P_q.rows() != n || terms.Qv.size() != 6 + n) {
    throw std::invalid_argument(std::string(where) + ": q_f (" + std::to_string(q_size) +
                                "), q̇_f (" + std::to_string(qd_size) + ") and the terms (" +
                                std::to_string(terms.P_q.rows()) + " modes) must all have " +
                                std::to_string(n) + " modes");
  }
}

}  // namespace detail

template <typename S>
InertiaTermsTpl<S> make_inertia_terms_tpl(int mode_count) {
  const Eigen::Index n = mode_count;
  InertiaTermsTpl<S> t;
  t.P_q = Eigen::Matrix<S, Eigen::Dynamic, 9>::Zero(n, 9);
  t.G_qd = Eigen::Matrix<S, Eigen::Dynamic, 3>::Zero(n, 3);
  t.block_scratch.gathered = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(n);
  t.block_scratch.product = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(n);
  t.P_t_qd = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(n);
  t.M_rr.setZero();
  t.M_rf = Eigen::Matrix<S, 6, Eigen::Dynamic>::Zero(6, n);
  t.Qv = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(6 + n);
  t.geometric_products = make_geometric_products_tpl<S>(mode_count);
  return t;
}

/// Stage 1 at (q_f, q̇_f): O(n²), allocates nothing. Throws std::invalid_argument on sizes.
template <typename S>
void compute_modal_products_tpl(const ModalInvariantsTpl<S>& inv, const VectorRef<S>& q_f,
                                const VectorRef<S>& qd_f, InertiaTermsTpl<S>& t) {
  using detail::pair_index;
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  detail::check_inertia_terms("compute_modal_products", inv, q_f.size(), qd_f.size(), t);
  if (inv.mode_count == 0) return;
  // Each stored P_ab (a ≤ b) is read, on its nonzero rows and columns, for P_ab q and, off the
  // diagonal, P_abᵀ q = P_ba q, and for g_a = G_a q̇_f = (P_bc − P_cb) q̇_f = P_bc q̇_f − P_bcᵀ q̇_f
  // ((a, b, c) cyclic; modal_invariants_tpl.hpp): no n×n product with a zero block.
  const auto block = [&](int a, int b) -> const CompressedBlockTpl<S>& {
    return inv.phi_phi_blocks[at(pair_index(a, b))];
  };
  for (int a = 0; a < 3; ++a) {
    // P_aa is exactly symmetric (make_modal_invariants): its lower triangle suffices.
    multiply_block_tpl<S>(block(a, a), q_f, t.P_q.col(pair_index(a, a)), t.block_scratch, false,
                          true);
    for (int b = a + 1; b < 3; ++b) {
      multiply_block_tpl<S>(block(a, b), q_f, t.P_q.col(pair_index(a, b)), t.block_scratch);
      multiply_block_tpl<S>(block(a, b), q_f, t.P_q.col(pair_index(b, a)), t.block_scratch, true);
    }
  }
  for (const auto& [a, b, c] : detail::kCyclicTriples) {
    // The stored pair of (b, c) is (min, max); P_cb q̇ = P_bcᵀ q̇.
    const bool stored_bc = b < c;
    const auto& P = block(std::min(b, c), std::max(b, c));
    multiply_block_tpl<S>(P, qd_f, t.G_qd.col(a), t.block_scratch, !stored_bc);
    multiply_block_tpl<S>(P, qd_f, t.P_t_qd, t.block_scratch, stored_bc);
    t.G_qd.col(a) -= t.P_t_qd;
  }
  t.X_q.noalias() = inv.x_phi * q_f;
  t.X_qd.noalias() = inv.x_phi * qd_f;
  t.S_q.noalias() = inv.S * q_f;
  t.S_qd.noalias() = inv.S * qd_f;
  if (inv.geometric) {
    compute_geometric_products_tpl<S>(*inv.geometric, q_f, qd_f, t.geometric_products);
  }
}

/// Stage 1 at q_f = 0, q̇_f = 0 (the LTE model's inertia terms): every product is zero, O(n).
template <typename S>
void set_undeformed_products_tpl(InertiaTermsTpl<S>& t) {
  t.P_q.setZero();
  t.G_qd.setZero();
  t.X_q.setZero();
  t.X_qd.setZero();
  t.S_q.setZero();
  t.S_qd.setZero();
  set_zero_geometric_products_tpl(t.geometric_products);
}

/// Stage 2 from the products of the same (q_f, q̇_f): M_rr, M_rf, Qv at attitude R_WB and
/// angular velocity w_B = ω̄. O(n), allocates nothing. Throws std::invalid_argument on sizes.
template <typename S>
void assemble_inertia_terms_tpl(const ModalInvariantsTpl<S>& inv,
                                const Eigen::Matrix<S, 3, 3>& R_WB, const VectorRef<S>& q_f,
                                const Eigen::Matrix<S, 3, 1>& w_B, const VectorRef<S>& qd_f,
                                InertiaTermsTpl<S>& t) {
  using detail::pair_index;
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  detail::check_inertia_terms("assemble_inertia_terms", inv, q_f.size(), qd_f.size(), t);
  const Eigen::Index n = inv.mode_count;
  const S half(0.5);
  const S two(2.0);
  t.R_WB = R_WB;
  t.s_t = inv.s0 + t.S_q;
  // Geometric stiffening: Δs, ΔS q̇, ΔJ, ΔC enter every formula below through s_t, S q̇, J, C.
  const bool geometric = inv.geometric.has_value();
  t.constant_translation_coupling = !geometric;
  ForeshorteningTermsTpl<S>& fs = t.foreshortening;
  if (geometric) {
    foreshortening_terms_tpl<S>(q_f, qd_f, t.geometric_products, fs);
    t.s_t += fs.ds;
  }
  const Vector3 S_qd = geometric ? Vector3(t.S_qd + fs.dS_qd) : t.S_qd;

  // J = J0 + L + Lᵀ + Q (exactly symmetric: L_ab + L_ba and the symmetrized Q commute).
  Matrix3 J;
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      const S L_sum = t.X_q(pair_index(a, b)) + t.X_q(pair_index(b, a));
      const S Q = a == b ? S(q_f.dot(t.P_q.col(pair_index(a, a))))
                         : S(half * (q_f.dot(t.P_q.col(pair_index(a, b))) +
                                     q_f.dot(t.P_q.col(pair_index(b, a)))));
      J(a, b) = inv.J0(a, b) + L_sum + Q + (geometric ? fs.dJ(a, b) : S(0));
      J(b, a) = J(a, b);
    }
  }
  t.I_tt = J.trace() * Matrix3::Identity() - J;

  // M_rr = [m I, −A s̃_t; s̃_t Aᵀ, Ī_θθ]
  t.M_rr.template topLeftCorner<3, 3>() = inv.mass * Matrix3::Identity();
  t.M_rr.template block<3, 3>(0, 3).noalias() = -R_WB * detail::hat_tpl<S>(t.s_t);
  t.M_rr.template block<3, 3>(3, 0) = t.M_rr.template block<3, 3>(0, 3).transpose();
  t.M_rr.template block<3, 3>(3, 3) = t.I_tt;

  // M_rf = [A S; Ī_θf]: A S column by column, Ī_θf row a = Ī_θf0 row a + (u_cb − u_bc)ᵀ.
  if (n > 0) {
    t.M_rf.template topRows<3>().noalias() = R_WB * inv.S;
    for (const auto& [a, b, c] : detail::kCyclicTriples) {
      t.M_rf.row(3 + a) = inv.I_theta_f0.row(a) +
                          (t.P_q.col(pair_index(c, b)) - t.P_q.col(pair_index(b, c))).transpose();
    }
    if (geometric) {
      // [A ΔS; ΔĪ_θf] with rows −(E_c q)ᵀ and −(Z_c q)ᵀ (GS-5, GS-7).
      t.M_rf.template topRows<3>().noalias() -= R_WB * t.geometric_products.E_q.transpose();
      t.M_rf.template bottomRows<3>() -= t.geometric_products.Z_q.transpose();
    }
  }

  // Qv (see inertia_terms.hpp).
  const Matrix3 W = detail::hat_tpl<S>(w_B);
  // W² = ω̄ω̄ᵀ − |ω̄|² I, exactly symmetric.
  const Matrix3 W2 = w_B * w_B.transpose() - w_B.squaredNorm() * Matrix3::Identity();
  Vector3 z_R = W2 * t.s_t + two * W * S_qd;
  if (geometric) z_R += fs.ds_vv;
  t.Qv.template head<3>().noalias() = -R_WB * z_R;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      t.C(a, b) = t.X_qd(pair_index(b, a)) + qd_f.dot(t.P_q.col(pair_index(a, b)));
    }
  }
  if (geometric) t.C += fs.dC;
  t.Qv.template segment<3>(3) = -W * (t.I_tt * w_B) - two * (t.C.trace() * w_B - t.C * w_B);
  if (geometric) t.Qv.template segment<3>(3) += fs.z_vv;
  if (n > 0) {
    // w9(3a+b) = (W²)_ab; Σ_ab (W²)_ab X_baᵀ = Xᵀ w9 since W² is symmetric.
    Eigen::Matrix<S, 9, 1> w9;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) w9(pair_index(a, b)) = W2(a, b);
    }
    auto Qv_f = t.Qv.tail(n);
    w9 = -w9;
    Qv_f.noalias() = inv.x_phi.transpose() * w9;
    Qv_f.noalias() += t.P_q * w9;
    Qv_f.noalias() += t.G_qd * (two * w_B);
    // Σ_ab (W²)_ab F_ab q_f (w9 holds −W² here).
    if (geometric) Qv_f.noalias() -= t.geometric_products.F_q * w9;
  }
}

}  // namespace flexref::flexible
