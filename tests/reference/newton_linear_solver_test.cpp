/// Tests of reference/newton_linear_solver: the SUNLinearSolver solves CVODE's dense Newton
/// matrix like a dense LU, refuses a matrix of the wrong size, and in a CVODE BDF integration
/// with the structured Jacobian (reference/ode_jacobian) gives a solution as accurate as
/// CVODE's own difference-quotient Jacobian and dense LU, in a similar number of steps.
#include "reference/newton_linear_solver.hpp"

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "reference/structured_jacobian.hpp"
#include "tests/support/floating_point.hpp"
#include "tests/support/jacobian_models.hpp"

namespace flexref::reference {
namespace {

using testing::kEps;

struct Sundials {
  Sundials() { SUNContext_Create(nullptr, &context); }
  ~Sundials() { SUNContext_Free(&context); }
  SUNContext context = nullptr;
};

TEST_CASE("the Newton linear solver solves CVODE's dense Newton matrix", "[reference][newton]") {
  const core::Model model = testing::spinner_and_block(core::FlexibleFormulation::kCoupled);
  const OdeForm form(model);
  const int N = form.size();
  const StructuredJacobian jacobian(form);
  StructuredJacobian::Scratch scratch = jacobian.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(N));
  form.pack(model.initial_state(), y.data());
  Eigen::MatrixXd J(N, N);
  jacobian.evaluate({0.25, 0.25}, y.data(), J, scratch);
  const double gamma = 2e-3;
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(N, N) - gamma * J;

  Sundials s;
  SUNMatrix M = SUNDenseMatrix(N, N, s.context);
  N_Vector x = N_VNew_Serial(N, s.context);
  N_Vector b = N_VNew_Serial(N, s.context);
  Eigen::Map<Eigen::MatrixXd>(SM_DATA_D(M), N, N) = A;
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(N, -1.0, 2.0);
  Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(b), N) = rhs;
  SUNLinearSolver LS = make_newton_linear_solver(form, s.context);
  CHECK(SUNLinSolGetType(LS) == SUNLINEARSOLVER_DIRECT);
  CHECK(SUNLinSolInitialize(LS) == SUNLS_SUCCESS);
  CHECK(SUNLinSolSetup(LS, M) == SUNLS_SUCCESS);
  CHECK(SUNLinSolSolve(LS, M, x, b, 0.0) == SUNLS_SUCCESS);
  const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(x), N);
  // Backward error of Gaussian elimination, as in newton_matrix_test.cpp: ≤ 10 N ε.
  const double A_norm = A.cwiseAbs().rowwise().sum().maxCoeff();
  CHECK((A * solution - rhs).cwiseAbs().maxCoeff() <=
        10.0 * N * kEps * (A_norm * solution.cwiseAbs().maxCoeff() + rhs.cwiseAbs().maxCoeff()));
  // A matrix without the pattern is a recoverable failure; a wrong size is illegal input.
  SM_ELEMENT_D(M, form.blocks()[0].q, form.blocks()[1].v) = 0.5;
  CHECK(SUNLinSolSetup(LS, M) == SUNLS_LUFACT_FAIL);
  SUNMatrix small = SUNDenseMatrix(N - 1, N - 1, s.context);
  CHECK(SUNLinSolSetup(LS, small) == SUNLS_ILL_INPUT);
  SUNMatDestroy(small);
  SUNLinSolFree(LS);
  N_VDestroy(b);
  N_VDestroy(x);
  SUNMatDestroy(M);
}

struct Run {
  std::vector<double> y;
  long steps = 0;
};

struct CvodeData {
  const OdeForm* form;
  OdeForm::Scratch scratch;
  const StructuredJacobian* jacobian;
  StructuredJacobian::Scratch jacobian_scratch;
};

int rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user) {
  auto& d = *static_cast<CvodeData*>(user);
  d.form->rhs({t, t}, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), d.scratch);
  return 0;
}

int jac(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector,
        N_Vector) {
  auto& d = *static_cast<CvodeData*>(user);
  d.jacobian->evaluate({t, t}, N_VGetArrayPointer(y), SM_DATA_D(J), static_cast<int>(SM_ROWS_D(J)),
                       d.jacobian_scratch);
  return 0;
}

/// CVODE BDF from the model's initial state to t_end, with either CVODE's own dense LU and
/// difference-quotient Jacobian or the structured pair.
Run integrate(const core::Model& model, double t_end, double rtol, bool structured) {
  const OdeForm form(model);
  const StructuredJacobian jacobian(form);
  CvodeData data{&form, form.make_scratch(), &jacobian, jacobian.make_scratch()};
  const int N = form.size();
  Sundials s;
  N_Vector y = N_VNew_Serial(N, s.context);
  form.pack(model.initial_state(), N_VGetArrayPointer(y));
  void* cvode = CVodeCreate(CV_BDF, s.context);
  CVodeInit(cvode, rhs, 0.0, y);
  CVodeSetUserData(cvode, &data);
  CVodeSStolerances(cvode, rtol, rtol);
  CVodeSetMaxNumSteps(cvode, 1000000);
  SUNMatrix J = SUNDenseMatrix(N, N, s.context);
  SUNLinearSolver LS =
      structured ? make_newton_linear_solver(form, s.context) : SUNLinSol_Dense(y, J, s.context);
  CVodeSetLinearSolver(cvode, LS, J);
  if (structured) CVodeSetJacFn(cvode, jac);
  double t = 0.0;
  REQUIRE(CVode(cvode, t_end, y, &t, CV_NORMAL) == CV_SUCCESS);
  Run run;
  CVodeGetNumSteps(cvode, &run.steps);
  run.y.assign(N_VGetArrayPointer(y), N_VGetArrayPointer(y) + N);
  CVodeFree(&cvode);
  SUNLinSolFree(LS);
  SUNMatDestroy(J);
  N_VDestroy(y);
  return run;
}

TEST_CASE("CVODE with the structured Jacobian and Newton solver is as accurate as without",
          "[reference][newton]") {
  // The pivot spinner under gravity (6 modes), 0.5 s: a stiff-ish flexible body in large motion.
  const core::Model model = testing::pivot_spinner(core::FlexibleFormulation::kCoupled);
  const double t_end = 0.5;
  const Run truth = integrate(model, t_end, 1e-12, false);
  const Run plain = integrate(model, t_end, 1e-8, false);
  const Run structured = integrate(model, t_end, 1e-8, true);
  const auto error = [&](const Run& r) {
    double e = 0.0;
    for (std::size_t i = 0; i < r.y.size(); ++i) e = std::max(e, std::abs(r.y[i] - truth.y[i]));
    return e;
  };
  INFO("plain error " << error(plain) << " in " << plain.steps << " steps; structured "
                      << error(structured) << " in " << structured.steps);
  // The two runs differ only in the Jacobian's rounding and the Newton matrix's solve, which
  // move the Newton iterates within CVODE's nonlinear tolerance: the errors agree in order of
  // magnitude (a factor 10 either way) and the step counts within 20 %. A wrong Jacobian block
  // or solve would slow Newton's convergence (more steps, failures) or fail the run.
  CHECK(error(plain) > 0.0);
  CHECK(error(structured) <= 10.0 * error(plain));
  CHECK(std::abs(structured.steps - plain.steps) <= plain.steps / 5);
}

}  // namespace
}  // namespace flexref::reference
