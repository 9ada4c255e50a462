/// \file mass_matrix_solve.cpp
/// See mass_matrix_solve.hpp for the algebra.
#include "flexible/mass_matrix_solve.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace flexref::flexible {
namespace {

void check(const char* where, const ModalMassFactor& factor, const InertiaTerms& terms, int known,
           Eigen::Index b_size, Eigen::Index x_size, const MassSolveScratch& scratch) {
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
void subtract_known_columns(const InertiaTerms& t, int known,
                            const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::VectorXd& b_f) {
  for (int k = 0; k < known; ++k) b_f.noalias() -= x(k) * t.M_rf.row(k).transpose();
}

/// x_u = Σ⁻¹ z (z in s.b_u) into x.segment(known, r); NaN when Σ was not positive definite (a
/// body without inertia about an axis), which solvers see as a failed evaluation and the
/// step-size control as a rejected step.
void solve_small(MassSolveScratch& s, Eigen::Ref<Eigen::VectorXd> x) {
  const Eigen::Index r = 6 - s.known;
  if (!s.factored) {
    x.segment(s.known, r).setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  x.segment(s.known, r) = s.schur_llt.solve(s.b_u);
}

}  // namespace

ModalMassFactor::ModalMassFactor(const ModalInvariants& inv) : llt_(inv.m_ff) {
  if (llt_.info() != Eigen::Success) {
    throw std::invalid_argument("the modal mass matrix m_ff is not positive definite");
  }
  Linv_St_ = inv.S.transpose();
  llt_.matrixL().solveInPlace(Linv_St_);
}

void ModalMassFactor::forward_in_place(Eigen::Ref<Eigen::VectorXd> v) const {
  llt_.matrixL().solveInPlace(v);
}

void ModalMassFactor::backward_in_place(Eigen::Ref<Eigen::VectorXd> v) const {
  llt_.matrixU().solveInPlace(v);
}

void ModalMassFactor::solve_in_place(Eigen::Ref<Eigen::VectorXd> v) const {
  forward_in_place(v);
  backward_in_place(v);
}

MassSolveScratch make_mass_solve_scratch(int mode_count) {
  MassSolveScratch s;
  s.Bhat_T = Eigen::Matrix<double, Eigen::Dynamic, 6>::Zero(mode_count, 6);
  s.b_f = Eigen::VectorXd::Zero(mode_count);
  s.schur.setZero(6, 6);
  s.b_u.setZero(6);
  return s;
}

void factor_coupled(const ModalMassFactor& factor, const InertiaTerms& t, int known,
                    MassSolveScratch& s) {
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

void apply_coupled(const ModalMassFactor& factor, const InertiaTerms& t,
                   const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
                   Eigen::Ref<Eigen::VectorXd> x) {
  const int known = s.known;
  check("apply_coupled", factor, t, known, b.size(), x.size(), s);
  const Eigen::Index n = factor.mode_count();
  const int r = 6 - known;
  s.b_f = b.tail(n);
  subtract_known_columns(t, known, x, s.b_f);
  if (r == 0) {
    factor.solve_in_place(s.b_f);
    x.tail(n) = s.b_f;
    return;
  }
  factor.forward_in_place(s.b_f);  // b̂
  // z = b_u − M_uk x_k − B̂ b̂
  for (int i = 0; i < r; ++i) {
    const int row = known + i;
    double z = b(row) - s.Bhat_T.col(row).dot(s.b_f);
    for (int k = 0; k < known; ++k) z -= t.M_rr(row, k) * x(k);
    s.b_u(i) = z;
  }
  solve_small(s, x);
  // x_f = L⁻ᵀ (b̂ − B̂ᵀ x_u)
  for (int u = known; u < 6; ++u) s.b_f.noalias() -= x(u) * s.Bhat_T.col(u);
  factor.backward_in_place(s.b_f);
  x.tail(n) = s.b_f;
}

void solve_coupled(const ModalMassFactor& factor, const InertiaTerms& t, int known,
                   const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
                   Eigen::Ref<Eigen::VectorXd> x) {
  check("solve_coupled", factor, t, known, b.size(), x.size(), s);
  factor_coupled(factor, t, known, s);
  apply_coupled(factor, t, b, s, x);
}

void factor_lte(const InertiaTerms& t, int known, MassSolveScratch& s) {
  const int r = 6 - known;
  s.known = known;
  s.schur.resize(r, r);
  s.b_u.resize(r);
  s.schur = t.M_rr.block(known, known, r, r);
  s.schur_llt.compute(s.schur);
  s.factored = r == 0 || s.schur_llt.info() == Eigen::Success;
}

void apply_lte(const ModalMassFactor& factor, const InertiaTerms& t,
               const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
               Eigen::Ref<Eigen::VectorXd> x) {
  const int known = s.known;
  check("apply_lte", factor, t, known, b.size(), x.size(), s);
  const int r = 6 - known;
  if (r > 0) {
    for (int i = 0; i < r; ++i) {
      const int row = known + i;
      double z = b(row);
      for (int k = 0; k < known; ++k) z -= t.M_rr(row, k) * x(k);
      s.b_u(i) = z;
    }
    solve_small(s, x);
  }
  solve_modal_rows(factor, t, b, s, x);
}

void solve_lte(const ModalMassFactor& factor, const InertiaTerms& t, int known,
               const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
               Eigen::Ref<Eigen::VectorXd> x) {
  check("solve_lte", factor, t, known, b.size(), x.size(), s);
  factor_lte(t, known, s);
  apply_lte(factor, t, b, s, x);
}

void solve_modal_rows(const ModalMassFactor& factor, const InertiaTerms& t,
                      const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
                      Eigen::Ref<Eigen::VectorXd> x) {
  check("solve_modal_rows", factor, t, 6, b.size(), x.size(), s);
  const Eigen::Index n = factor.mode_count();
  s.b_f = b.tail(n);
  subtract_known_columns(t, 6, x, s.b_f);
  factor.solve_in_place(s.b_f);
  x.tail(n) = s.b_f;
}

}  // namespace flexref::flexible
