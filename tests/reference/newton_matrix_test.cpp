/// Tests of reference/newton_matrix: the structured solve of A = I − γJ (J the ODE form's
/// Jacobian) is backward stable and agrees with a dense LU solve, on a free flexible body
/// tethered to a rigid one (two attitudes, the dissipated work), a pivot flexible body, a
/// prescribed one (no attitude) and a rigid pivot body, for small and large γ; it refuses a
/// matrix without the kinematic pattern; it allocates nothing.
#include "reference/newton_matrix.hpp"

#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "reference/structured_jacobian.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/floating_point.hpp"
#include "tests/support/jacobian_models.hpp"
#include "tests/support/test_models.hpp"

namespace flexref::reference {
namespace {

using testing::kEps;

/// A = I − γ J at a random state of the model.
Eigen::MatrixXd newton_matrix(const OdeForm& form, double gamma, double t, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<double> y(static_cast<std::size_t>(form.size()));
  for (double& v : y) v = normal(rng);
  for (const OdeForm::Block& k : form.blocks()) {
    for (int i = 0; i < k.n; ++i) y[static_cast<std::size_t>(k.q + i)] *= 0.05;
  }
  const StructuredJacobian jacobian(form);
  StructuredJacobian::Scratch scratch = jacobian.make_scratch();
  Eigen::MatrixXd J(form.size(), form.size());
  jacobian.evaluate({t, t}, y.data(), J, scratch);
  return Eigen::MatrixXd::Identity(form.size(), form.size()) - gamma * J;
}

void check_solves(const core::Model& model, double t, unsigned seed) {
  const OdeForm form(model);
  NewtonMatrixSolver solver(form);
  const int N = form.size();
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  for (const double gamma : {1e-5, 1e-3, 3e-2}) {
    INFO("gamma " << gamma);
    const Eigen::MatrixXd A = newton_matrix(form, gamma, t, seed);
    REQUIRE(solver.factor(A.data(), N));
    Eigen::VectorXd b(N);
    for (int i = 0; i < N; ++i) b(i) = normal(rng);
    Eigen::VectorXd x = b;
    solver.solve(x.data());
    // Normwise backward error of Gaussian elimination: ≤ γ_{3N} ρ with a growth factor ρ of a
    // few (the P pivots are 1 or the near-identity θ blocks; S is as well scaled as A);
    // 10 N ε allows ρ ≤ 3.
    const double A_norm = A.cwiseAbs().rowwise().sum().maxCoeff();
    const double eta = (A * x - b).cwiseAbs().maxCoeff() /
                       (A_norm * x.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff());
    CHECK(eta <= 10.0 * N * kEps);
    // Forward agreement with a dense LU: both backward stable, so |x − x_dense| ≤ 2 κ η_max |x|.
    const Eigen::PartialPivLU<Eigen::MatrixXd> dense(A);
    const Eigen::VectorXd x_dense = dense.solve(b);
    const double kappa = A_norm * dense.inverse().cwiseAbs().rowwise().sum().maxCoeff();
    CHECK((x - x_dense).cwiseAbs().maxCoeff() <=
          2.0 * kappa * 10.0 * N * kEps * x_dense.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("the structured Newton solve equals a dense LU solve", "[reference][newton]") {
  check_solves(testing::spinner_and_block(core::FlexibleFormulation::kCoupled), 0.25, 1);
  check_solves(testing::spinner_and_block(core::FlexibleFormulation::kLte), 0.25, 2);
  check_solves(testing::pivot_spinner(core::FlexibleFormulation::kCoupled), 0.25, 3);
  check_solves(testing::rotating_cantilever_model(core::FlexibleFormulation::kCoupled, 3.0, 4), 0.7,
               4);
  check_solves(testing::heavy_top_model(), 0.05, 5);
}

TEST_CASE("the structured Newton solve refuses a matrix without the kinematic pattern",
          "[reference][newton]") {
  const core::Model model = testing::spinner_and_block(core::FlexibleFormulation::kCoupled);
  const OdeForm form(model);
  NewtonMatrixSolver solver(form);
  const int N = form.size();
  const Eigen::MatrixXd A = newton_matrix(form, 1e-3, 0.25, 7);
  REQUIRE(solver.factor(A.data(), N));
  const OdeForm::Block& s = form.blocks()[0];
  Eigen::MatrixXd bad = A;
  bad(s.q, s.w) = 1e-3;  // a modal coordinate's rate depending on ω̄
  CHECK_FALSE(solver.factor(bad.data(), N));
  bad = A;
  bad(s.p, s.p + 1) = 1e-3;  // a position depending on another position
  CHECK_FALSE(solver.factor(bad.data(), N));
  bad = A;
  bad(s.v, form.work_index()) = 1e-3;  // an acceleration depending on the dissipated work
  CHECK_FALSE(solver.factor(bad.data(), N));
  // A leading dimension larger than N reads the same matrix.
  Eigen::MatrixXd padded = Eigen::MatrixXd::Constant(N + 3, N, 7.0);
  padded.topRows(N) = A;
  CHECK(solver.factor(padded.data(), N + 3));
}

TEST_CASE("the structured Newton solve allocates nothing", "[reference][newton]") {
  const core::Model model = testing::spinner_and_block(core::FlexibleFormulation::kCoupled);
  const OdeForm form(model);
  NewtonMatrixSolver solver(form);
  const Eigen::MatrixXd A = newton_matrix(form, 1e-3, 0.25, 9);
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(form.size(), -1.0, 1.0);
  bool ok = false;
  CHECK(testing::count_allocations([&] {
          ok = solver.factor(A.data(), form.size());
          solver.solve(x.data());
        }) == 0);
  CHECK(ok);
  CHECK(x.allFinite());
  CHECK(solver.reduced_size() == 6 + 8 + 6);  // spinner (8 modes) and block velocities
}

}  // namespace
}  // namespace flexref::reference
