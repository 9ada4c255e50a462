#pragma once
/// \file mass_matrix_solve_tpl.hpp
/// The structured solves with one flexible body's mass matrix (flexible/mass_matrix_solve.hpp
/// gives the algebra) written once for any scalar type S: double (ModalMassFactor and the solves
/// every integrator uses) and the extended and quad precisions of precision/.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "flexible/inertia_terms_tpl.hpp"
#include "flexible/modal_invariants_tpl.hpp"

namespace flexref::flexible {

/// The constant part: the Cholesky factor of m_ff and L⁻¹ Sᵀ (n×3). Built once per body.
///
/// Mode families that share no node direction (a beam's bending-xy and bending-xz modes) make
/// m_ff block diagonal up to a permutation P of the modes. The factor then works in the
/// permuted order, m_ff = Pᵀ L Lᵀ P with L block diagonal, one dense Cholesky factor per group
/// of coupled modes: forward (v ← L⁻¹ P v) and backward (v ← Pᵀ L⁻ᵀ v) substitutions skip the
/// zero blocks (half the work for two equal families; docs/precision.md, "Many modes"). The
/// structured solves only use L-space vectors between a forward and a backward substitution
/// (B̂ = L⁻¹ P M_fr, b̂), so Σ = M_uu − B̂ᵀB̂ and the solution are those of the unpermuted
/// factor. With one group (every mode coupled to every other) P is the identity and the factor
/// is m_ff's dense Cholesky factor.
template <typename S>
class ModalMassFactorTpl {
 public:
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

  ModalMassFactorTpl() = default;
  /// Throws std::invalid_argument when m_ff is not positive definite.
  explicit ModalMassFactorTpl(const ModalInvariantsTpl<S>& inv) {
    const Matrix& m_ff = inv.m_ff;
    group_modes(m_ff);
    for (std::size_t k = 0; k + 1 < offsets_.size(); ++k) {
      const Eigen::Index begin = offsets_[k], size = offsets_[k + 1] - offsets_[k];
      Matrix block(size, size);
      for (Eigen::Index i = 0; i < size; ++i) {
        for (Eigen::Index j = 0; j < size; ++j) {
          block(i, j) = m_ff(order_[static_cast<std::size_t>(begin + i)],
                             order_[static_cast<std::size_t>(begin + j)]);
        }
      }
      blocks_.emplace_back(block);
      if (blocks_.back().info() != Eigen::Success) {
        throw std::invalid_argument("the modal mass matrix m_ff is not positive definite");
      }
    }
    Linv_St_ = inv.S.transpose();
    for (int c = 0; c < 3; ++c) forward_in_place(Linv_St_.col(c));
  }

  int mode_count() const { return static_cast<int>(Linv_St_.rows()); }
  /// The groups of coupled modes (1 when every mode couples to every other).
  int group_count() const { return static_cast<int>(blocks_.size()); }
  /// The mode at each permuted position (P v = (v[order[0]], v[order[1]], …)).
  const std::vector<Eigen::Index>& order() const { return order_; }
  /// L⁻¹ P Sᵀ (n×3).
  const Eigen::Matrix<S, Eigen::Dynamic, 3>& Linv_St() const { return Linv_St_; }
  /// v ← L⁻¹ P v (permutation, then forward substitution per group), allocation-free.
  void forward_in_place(Eigen::Ref<Vector> v) const {
    permute_in_place(v, order_);
    for (std::size_t k = 0; k < blocks_.size(); ++k) {
      auto segment = v.segment(offsets_[k], offsets_[k + 1] - offsets_[k]);
      blocks_[k].matrixL().solveInPlace(segment);
    }
  }
  /// v ← Pᵀ L⁻ᵀ v (backward substitution per group, then the inverse permutation),
  /// allocation-free.
  void backward_in_place(Eigen::Ref<Vector> v) const {
    for (std::size_t k = 0; k < blocks_.size(); ++k) {
      auto segment = v.segment(offsets_[k], offsets_[k + 1] - offsets_[k]);
      blocks_[k].matrixU().solveInPlace(segment);
    }
    permute_in_place(v, position_);
  }
  /// v ← m_ff⁻¹ v.
  void solve_in_place(Eigen::Ref<Vector> v) const {
    forward_in_place(v);
    backward_in_place(v);
  }

 private:
  /// Connected components of m_ff's nonzero pattern, each in ascending mode order, ordered by
  /// their first mode: order_[k] is the mode at permuted position k, position_ its inverse.
  void group_modes(const Matrix& m_ff) {
    const auto n = static_cast<std::size_t>(m_ff.rows());
    std::vector<int> group(n, -1);
    offsets_.assign(1, 0);
    order_.clear();
    for (std::size_t seed = 0; seed < n; ++seed) {
      if (group[seed] >= 0) continue;
      const int g = static_cast<int>(offsets_.size()) - 1;
      std::vector<std::size_t> members{seed};
      group[seed] = g;
      for (std::size_t i = 0; i < members.size(); ++i) {
        for (std::size_t j = 0; j < n; ++j) {
          const auto r = static_cast<Eigen::Index>(members[i]), c = static_cast<Eigen::Index>(j);
          if (group[j] < 0 && m_ff(r, c) != S(0)) {
            group[j] = g;
            members.push_back(j);
          }
        }
      }
      std::sort(members.begin(), members.end());
      for (std::size_t m : members) order_.push_back(static_cast<Eigen::Index>(m));
      offsets_.push_back(static_cast<Eigen::Index>(order_.size()));
    }
    position_.assign(n, 0);
    for (std::size_t k = 0; k < n; ++k)
      position_[static_cast<std::size_t>(order_[k])] = static_cast<Eigen::Index>(k);
    // The cycles of the permutation, each walked from its smallest member (permute_in_place).
    cycle_starts_.clear();
    std::vector<bool> seen(n, false);
    for (std::size_t k = 0; k < n; ++k) {
      if (seen[k] || order_[k] == static_cast<Eigen::Index>(k)) continue;
      cycle_starts_.push_back(static_cast<Eigen::Index>(k));
      for (std::size_t j = k; !seen[j]; j = static_cast<std::size_t>(order_[j])) seen[j] = true;
    }
  }
  /// v ← (v[from[0]], v[from[1]], …) in place along the permutation's cycles (order_ and
  /// position_ have the same cycles, walked in opposite directions).
  void permute_in_place(Eigen::Ref<Vector> v, const std::vector<Eigen::Index>& from) const {
    for (const Eigen::Index start : cycle_starts_) {
      const S first = v(start);
      Eigen::Index k = start;
      while (from[static_cast<std::size_t>(k)] != start) {
        v(k) = v(from[static_cast<std::size_t>(k)]);
        k = from[static_cast<std::size_t>(k)];
      }
      v(k) = first;
    }
  }

  std::vector<Eigen::LLT<Matrix>> blocks_;  ///< one Cholesky factor per group
  std::vector<Eigen::Index> offsets_{0};    ///< group k is positions [offsets_[k], offsets_[k+1])
  std::vector<Eigen::Index> order_;         ///< the mode at each permuted position
  std::vector<Eigen::Index> position_;      ///< the permuted position of each mode
  std::vector<Eigen::Index> cycle_starts_;
  Eigen::Matrix<S, Eigen::Dynamic, 3> Linv_St_;
};

/// Scratch of the structured solves, sized once for n modes (make_mass_solve_scratch).
template <typename S>
struct MassSolveScratchTpl {
  using Small = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
  Eigen::Matrix<S, Eigen::Dynamic, 6> Bhat_T;  ///< column u: L⁻¹ (row u of M_rf)ᵀ (n×6)
  Eigen::Matrix<S, Eigen::Dynamic, 1> b_f;     ///< the modal right-hand side, then b̂, x_f
  Small schur;
  /// Factored on an empty matrix until used: an Eigen::LLT never computed holds an
  /// indeterminate ComputationInfo, and copying one reads it (UBSan: invalid enum load).
  Eigen::LLT<Small> schur_llt{Small()};
  Eigen::Matrix<S, Eigen::Dynamic, 1, 0, 6, 1> b_u;
  int known = 0;          ///< known rows of the last factorization
  bool factored = false;  ///< false: Σ (or M_uu) was not positive definite
};

template <typename S>
MassSolveScratchTpl<S> make_mass_solve_scratch_tpl(int mode_count) {
  MassSolveScratchTpl<S> s;
  s.Bhat_T = Eigen::Matrix<S, Eigen::Dynamic, 6>::Zero(mode_count, 6);
  s.b_f = Eigen::Matrix<S, Eigen::Dynamic, 1>::Zero(mode_count);
  s.schur.setZero(6, 6);
  s.b_u.setZero(6);
  return s;
}

namespace detail {

template <typename S>
void check_solve(const char* where, const ModalMassFactorTpl<S>& factor,
                 const InertiaTermsTpl<S>& terms, int known, Eigen::Index b_size,
                 Eigen::Index x_size, const MassSolveScratchTpl<S>& scratch) {
  const Eigen::Index n = factor.mode_count();
  if (known < 0 || known > 6 || terms.mode_count() != n || b_size != 6 + n || x_size != 6 + n ||
      scratch.b_f.size() != n) {
    throw std::invalid_argument(std::string(where) + ": sizes do not match " + std::to_string(n) +
                                " modes (b " + std::to_string(b_size) + ", x " +
                                std::to_string(x_size) + ", known rows " + std::to_string(known) +
                                ")");
  }
}

/// b_f ← b_f − Σ_{k<known} x_k (row k of M_rf)ᵀ: the modal rows' share of the known rows.
template <typename S>
void subtract_known_columns(const InertiaTermsTpl<S>& t, int known,
                            const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& x,
                            Eigen::Matrix<S, Eigen::Dynamic, 1>& b_f) {
  for (int k = 0; k < known; ++k) b_f.noalias() -= x(k) * t.M_rf.row(k).transpose();
}

/// x_u = Σ⁻¹ z (z in s.b_u) into x.segment(known, r); NaN when Σ was not positive definite (a
/// body without inertia about an axis), which solvers see as a failed evaluation and the
/// step-size control as a rejected step.
template <typename S>
void solve_small(MassSolveScratchTpl<S>& s, Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> x) {
  const Eigen::Index r = 6 - s.known;
  if (!s.factored) {
    x.segment(s.known, r).setConstant(std::numeric_limits<S>::quiet_NaN());
    return;
  }
  x.segment(s.known, r) = s.schur_llt.solve(s.b_u);
}

}  // namespace detail

/// The factorization of the coupled system (mass_matrix_solve.hpp, factor_coupled).
template <typename S>
void factor_coupled_tpl(const ModalMassFactorTpl<S>& factor, const InertiaTermsTpl<S>& t, int known,
                        MassSolveScratchTpl<S>& s) {
  const int r = 6 - known;
  s.known = known;
  s.schur.resize(r, r);
  s.b_u.resize(r);
  if (r == 0) {
    s.factored = true;
    return;
  }
  // B̂ᵀ column u = L⁻¹ (row u of M_rf)ᵀ: translation rows L⁻¹ Sᵀ A.row(u)ᵀ (constant L⁻¹ Sᵀ;
  // with geometric stiffening they depend on q_f), the others by forward substitution.
  for (int u = known; u < 6; ++u) {
    if (u < 3 && t.constant_translation_coupling) {
      s.Bhat_T.col(u).noalias() = factor.Linv_St() * t.R_WB.row(u).transpose();
    } else {
      s.Bhat_T.col(u) = t.M_rf.row(u).transpose();
      factor.forward_in_place(s.Bhat_T.col(u));
    }
  }
  // Σ = M_uu − B̂ B̂ᵀ (exactly symmetric).
  for (int i = 0; i < r; ++i) {
    for (int j = 0; j <= i; ++j) {
      s.schur(i, j) =
          t.M_rr(known + i, known + j) - s.Bhat_T.col(known + i).dot(s.Bhat_T.col(known + j));
      s.schur(j, i) = s.schur(i, j);
    }
  }
  s.schur_llt.compute(s.schur);
  s.factored = s.schur_llt.info() == Eigen::Success;
}

/// Its application to one right-hand side (mass_matrix_solve.hpp, apply_coupled).
template <typename S>
void apply_coupled_tpl(const ModalMassFactorTpl<S>& factor, const InertiaTermsTpl<S>& t,
                       const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& b,
                       MassSolveScratchTpl<S>& s,
                       Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> x) {
  const int known = s.known;
  detail::check_solve("apply_coupled", factor, t, known, b.size(), x.size(), s);
  const Eigen::Index n = factor.mode_count();
  const int r = 6 - known;
  s.b_f = b.tail(n);
  detail::subtract_known_columns<S>(t, known, x, s.b_f);
  if (r == 0) {
    factor.solve_in_place(s.b_f);
    x.tail(n) = s.b_f;
    return;
  }
  factor.forward_in_place(s.b_f);  // b̂
  // z = b_u − M_uk x_k − B̂ b̂
  for (int i = 0; i < r; ++i) {
    const int row = known + i;
    S z = b(row) - s.Bhat_T.col(row).dot(s.b_f);
    for (int k = 0; k < known; ++k) z -= t.M_rr(row, k) * x(k);
    s.b_u(i) = z;
  }
  detail::solve_small<S>(s, x);
  // x_f = L⁻ᵀ (b̂ − B̂ᵀ x_u)
  for (int u = known; u < 6; ++u) s.b_f.noalias() -= x(u) * s.Bhat_T.col(u);
  factor.backward_in_place(s.b_f);
  x.tail(n) = s.b_f;
}

/// The factorization of the LTE system: the Cholesky factor of M_uu.
template <typename S>
void factor_lte_tpl(const InertiaTermsTpl<S>& t, int known, MassSolveScratchTpl<S>& s) {
  const int r = 6 - known;
  s.known = known;
  s.schur.resize(r, r);
  s.b_u.resize(r);
  s.schur = t.M_rr.block(known, known, r, r);
  s.schur_llt.compute(s.schur);
  s.factored = r == 0 || s.schur_llt.info() == Eigen::Success;
}

/// The modal rows: x.tail(n) = m_ff⁻¹ (b_f − M_rfᵀ x.head(6)), x.head(6) given.
template <typename S>
void solve_modal_rows_tpl(const ModalMassFactorTpl<S>& factor, const InertiaTermsTpl<S>& t,
                          const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& b,
                          MassSolveScratchTpl<S>& s,
                          Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> x) {
  detail::check_solve("solve_modal_rows", factor, t, 6, b.size(), x.size(), s);
  const Eigen::Index n = factor.mode_count();
  s.b_f = b.tail(n);
  detail::subtract_known_columns<S>(t, 6, x, s.b_f);
  factor.solve_in_place(s.b_f);
  x.tail(n) = s.b_f;
}

/// The LTE system's application to one right-hand side (mass_matrix_solve.hpp, apply_lte).
template <typename S>
void apply_lte_tpl(const ModalMassFactorTpl<S>& factor, const InertiaTermsTpl<S>& t,
                   const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& b,
                   MassSolveScratchTpl<S>& s, Eigen::Ref<Eigen::Matrix<S, Eigen::Dynamic, 1>> x) {
  const int known = s.known;
  detail::check_solve("apply_lte", factor, t, known, b.size(), x.size(), s);
  const int r = 6 - known;
  if (r > 0) {
    for (int i = 0; i < r; ++i) {
      const int row = known + i;
      S z = b(row);
      for (int k = 0; k < known; ++k) z -= t.M_rr(row, k) * x(k);
      s.b_u(i) = z;
    }
    detail::solve_small<S>(s, x);
  }
  solve_modal_rows_tpl<S>(factor, t, b, s, x);
}

}  // namespace flexref::flexible
