/// \file mass_matrix_solve.cpp
/// See mass_matrix_solve.hpp for the algebra.
#include "flexible/mass_matrix_solve.hpp"

namespace flexref::flexible {

MassSolveScratch make_mass_solve_scratch(int mode_count) {
  return make_mass_solve_scratch_tpl<double>(mode_count);
}

void factor_coupled(const ModalMassFactor& factor, const InertiaTerms& t, int known,
                    MassSolveScratch& s) {
  factor_coupled_tpl(factor, t, known, s);
}

void apply_coupled(const ModalMassFactor& factor, const InertiaTerms& t,
                   const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
                   Eigen::Ref<Eigen::VectorXd> x) {
  apply_coupled_tpl<double>(factor, t, b, s, x);
}

void solve_coupled(const ModalMassFactor& factor, const InertiaTerms& t, int known,
                   const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
                   Eigen::Ref<Eigen::VectorXd> x) {
  detail::check_solve("solve_coupled", factor, t, known, b.size(), x.size(), s);
  factor_coupled(factor, t, known, s);
  apply_coupled(factor, t, b, s, x);
}

void factor_lte(const InertiaTerms& t, int known, MassSolveScratch& s) {
  factor_lte_tpl(t, known, s);
}

void apply_lte(const ModalMassFactor& factor, const InertiaTerms& t,
               const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
               Eigen::Ref<Eigen::VectorXd> x) {
  apply_lte_tpl<double>(factor, t, b, s, x);
}

void solve_lte(const ModalMassFactor& factor, const InertiaTerms& t, int known,
               const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
               Eigen::Ref<Eigen::VectorXd> x) {
  detail::check_solve("solve_lte", factor, t, known, b.size(), x.size(), s);
  factor_lte(t, known, s);
  apply_lte(factor, t, b, s, x);
}

void solve_modal_rows(const ModalMassFactor& factor, const InertiaTerms& t,
                      const Eigen::Ref<const Eigen::VectorXd>& b, MassSolveScratch& s,
                      Eigen::Ref<Eigen::VectorXd> x) {
  solve_modal_rows_tpl<double>(factor, t, b, s, x);
}

}  // namespace flexref::flexible
