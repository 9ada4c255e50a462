/// \file ida_newton_solver.cpp
/// See ida_newton_solver.hpp.
#include "reference/ida_newton_solver.hpp"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cstddef>
#include <new>

#include "reference/custom_linear_solver.hpp"

namespace flexref::reference {

IdaNewtonSystem::IdaNewtonSystem(const DaeForm& dae, const OdeForm& ode)
    : newton_(ode), dae_(&dae) {
  for (const DaeForm::Block& k : dae.blocks()) {
    for (int j = 0; j < 3; ++j) {
      if (k.v >= 0) velocity_.push_back(k.v + j);
    }
    for (int j = 0; j < 3; ++j) {
      if (k.w >= 0) velocity_.push_back(k.w + j);
    }
    for (int j = 0; j < k.n; ++j) velocity_.push_back(k.qd + j);
  }
  const int n = dae.size();
  const auto v = static_cast<Eigen::Index>(velocity_.size());
  mass_ = Eigen::MatrixXd::Identity(n, n);
  mass_VV_ = Eigen::MatrixXd::Identity(v, v);
  mass_lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(mass_VV_);
  b_V_ = Eigen::VectorXd::Zero(v);
  x_V_ = Eigen::VectorXd::Zero(v);
}

bool IdaNewtonSystem::setup_matrix(const core::LoadContext& context, const double* y, double c_j,
                                   double* J, DaeForm::Scratch& scratch) {
  const int n = size();
  Eigen::Map<Eigen::MatrixXd> A(J, n, n);
  A *= -1.0 / c_j;
  A.diagonal().array() += 1.0;
  c_j_ = c_j;
  dae_->mass_rows(context, y, mass_, scratch);
  const auto v = velocity_.size();
  for (std::size_t c = 0; c < v; ++c) {
    for (std::size_t r = 0; r < v; ++r) {
      mass_VV_(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) =
          mass_(velocity_[r], velocity_[c]);
    }
  }
  if (!mass_VV_.allFinite()) return false;
  mass_lu_.compute(mass_VV_);
  return true;
}

void IdaNewtonSystem::solve(double* x) const {
  const auto v = velocity_.size();
  for (std::size_t r = 0; r < v; ++r) b_V_(static_cast<Eigen::Index>(r)) = x[velocity_[r]];
  x_V_.noalias() = mass_lu_.solve(b_V_);
  for (std::size_t r = 0; r < v; ++r) x[velocity_[r]] = x_V_(static_cast<Eigen::Index>(r));
  newton_.solve(x);
  Eigen::Map<Eigen::VectorXd>(x, size()) /= c_j_;
}

namespace {
namespace ida_ops {

struct Content {
  IdaNewtonSystem* system = nullptr;
  sunindextype last_flag = SUNLS_SUCCESS;
};

Content& content(SUNLinearSolver S) { return sundials::solver_content<Content>(S); }

int initialize(SUNLinearSolver S) {
  content(S).last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

int setup(SUNLinearSolver S, SUNMatrix A) {
  Content& c = content(S);
  if (SUNMatGetID(A) != SUNMATRIX_DENSE || SM_ROWS_D(A) != c.system->size() ||
      SM_COLUMNS_D(A) != c.system->size()) {
    c.last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  c.last_flag = c.system->factor(SM_DATA_D(A)) ? SUNLS_SUCCESS : SUNLS_LUFACT_FAIL;
  return static_cast<int>(c.last_flag);
}

int solve(SUNLinearSolver S, SUNMatrix /*A*/, N_Vector x, N_Vector b, realtype /*tol*/) {
  Content& c = content(S);
  N_VScale(1.0, b, x);
  c.system->solve(N_VGetArrayPointer(x));
  c.last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

sunindextype last_flag(SUNLinearSolver S) { return content(S).last_flag; }

}  // namespace ida_ops
}  // namespace

SUNLinearSolver make_ida_newton_linear_solver(IdaNewtonSystem& system, SUNContext context) {
  return sundials::make_custom_solver<ida_ops::Content>(
      context, {ida_ops::initialize, ida_ops::setup, ida_ops::solve, ida_ops::last_flag}, &system);
}

}  // namespace flexref::reference
