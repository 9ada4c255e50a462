/// \file ida_work_completion.cpp
/// See ida_work_completion.hpp.
#include "reference/ida_work_completion.hpp"

#include <nvector/nvector_serial.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <new>

#include "reference/custom_linear_solver.hpp"

namespace flexref::reference {

IdaWorkCompletion::IdaWorkCompletion(const DaeForm& form)
    : form_(&form), first_(form.work_index()), count_(form.integral_count()) {
  const auto n = static_cast<std::size_t>(form.size());
  for (std::vector<double>* v : {&y_, &yp_, &r_, &ewt_, &y_moved_, &yp_moved_, &r_moved_}) {
    v->assign(n, 0.0);
  }
}

void IdaWorkCompletion::remember(double t, double t_segment, const double* y, const double* yp,
                                 const double* r) {
  t_ = t;
  t_segment_ = t_segment;
  std::copy(y, y + y_.size(), y_.begin());
  std::copy(yp, yp + yp_.size(), yp_.begin());
  std::copy(r, r + r_.size(), r_.begin());
}

void IdaWorkCompletion::set_matrix(double c_j, const double* ewt) {
  c_j_ = c_j;
  std::copy(ewt, ewt + ewt_.size(), ewt_.begin());
}

bool IdaWorkCompletion::complete(double* x, DaeForm::Scratch& scratch) {
  const auto n = y_.size();
  const auto is_work = [this](std::size_t k) {
    return static_cast<int>(k) >= first_ && static_cast<int>(k) < first_ + count_;
  };
  // σ = 1/‖x_s‖_WRMS (the works' entries left out: the direction is the state's)
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!is_work(k)) sum += (x[k] * ewt_[k]) * (x[k] * ewt_[k]);
  }
  if (!(sum > 0.0)) return std::isfinite(sum);
  const double sigma = 1.0 / std::sqrt(sum / static_cast<double>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const double v = is_work(k) ? 0.0 : x[k];
    y_moved_[k] = y_[k] + sigma * v;
    yp_moved_[k] = yp_[k] + (c_j_ * sigma) * v;
  }
  form_->residual(core::LoadContext{t_, t_segment_}, y_moved_.data(), yp_moved_.data(),
                  r_moved_.data(), scratch);
  ++residuals_;
  for (int j = first_; j < first_ + count_; ++j) {
    const auto k = static_cast<std::size_t>(j);
    const double G_Ws_x = (r_moved_[k] - r_[k]) / sigma;
    if (!std::isfinite(G_Ws_x)) return false;
    x[k] -= G_Ws_x / c_j_;
  }
  return true;
}

namespace {
namespace completing_ops {

struct Content {
  SUNLinearSolver klu = nullptr;
  IdaWorkCompletion* completion = nullptr;
  DaeForm::Scratch* scratch = nullptr;
  sunindextype last_flag = SUNLS_SUCCESS;
};

Content& content(SUNLinearSolver S) { return sundials::solver_content<Content>(S); }

int initialize(SUNLinearSolver S) {
  content(S).last_flag = SUNLinSolInitialize(content(S).klu);
  return static_cast<int>(content(S).last_flag);
}
int setup(SUNLinearSolver S, SUNMatrix A) {
  content(S).last_flag = SUNLinSolSetup(content(S).klu, A);
  return static_cast<int>(content(S).last_flag);
}
int solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, realtype tol) {
  Content& c = content(S);
  c.last_flag = SUNLinSolSolve(c.klu, A, x, b, tol);
  if (c.last_flag != SUNLS_SUCCESS) return static_cast<int>(c.last_flag);
  // A residual that is not finite: recoverable, as a failed factorization (IDA cuts the step).
  c.last_flag = c.completion->complete(N_VGetArrayPointer(x), *c.scratch) ? SUNLS_SUCCESS
                                                                          : SUNLS_PACKAGE_FAIL_REC;
  return static_cast<int>(c.last_flag);
}
sunindextype last_flag(SUNLinearSolver S) { return content(S).last_flag; }

}  // namespace completing_ops
}  // namespace

SUNLinearSolver make_ida_work_completing_solver(SUNLinearSolver klu, IdaWorkCompletion& completion,
                                                DaeForm::Scratch& scratch, SUNContext context) {
  return sundials::make_custom_solver<completing_ops::Content>(
      context,
      {completing_ops::initialize, completing_ops::setup, completing_ops::solve,
       completing_ops::last_flag},
      klu, &completion, &scratch);
}

}  // namespace flexref::reference
