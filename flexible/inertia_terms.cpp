/// \file inertia_terms.cpp
/// See inertia_terms.hpp for the formulas.
#include "flexible/inertia_terms.hpp"

namespace flexref::flexible {

InertiaTerms make_inertia_terms(int mode_count) {
  return make_inertia_terms_tpl<double>(mode_count);
}

void compute_modal_products(const ModalInvariants& inv,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& t) {
  compute_modal_products_tpl<double>(inv, q_f, qd_f, t);
}

void set_undeformed_products(InertiaTerms& t) { set_undeformed_products_tpl(t); }

void assemble_inertia_terms(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Vector3d& w_B,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& t) {
  assemble_inertia_terms_tpl<double>(inv, R_WB, q_f, w_B, qd_f, t);
}

void evaluate_inertia_terms(const ModalInvariants& inv, const Eigen::Matrix3d& R_WB,
                            const Eigen::Ref<const Eigen::VectorXd>& q_f,
                            const Eigen::Vector3d& w_B,
                            const Eigen::Ref<const Eigen::VectorXd>& qd_f, InertiaTerms& t) {
  compute_modal_products(inv, q_f, qd_f, t);
  assemble_inertia_terms(inv, R_WB, q_f, w_B, qd_f, t);
}

}  // namespace flexref::flexible
