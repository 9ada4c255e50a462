/// \file ode_jacobian_test.cpp
/// The user-Jacobian hook of the implicit references (reference/ode_jacobian.hpp): CVODE and IDA
/// given ∂f/∂y (here by central differences, standing in for an analytic or structured one) use
/// it instead of their own difference quotients and reach the same solution.
#include "reference/ode_jacobian.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

/// ∂f/∂y by central differences, step ε^(1/3)·max(1, |y_j|) (the optimum for a central
/// difference), and the number of calls. Buffers sized once; evaluations allocate nothing.
class CentralDifferenceJacobian final : public OdeJacobian {
 public:
  explicit CentralDifferenceJacobian(int n)
      : y_(static_cast<std::size_t>(n)), plus_(y_.size()), minus_(y_.size()) {}

  void evaluate(const OdeForm& form, const core::LoadContext& context, const double* y,
                const double* /*fy*/, Eigen::Ref<Eigen::MatrixXd> jacobian,
                OdeForm::Scratch& scratch) const override {
    ++calls;
    const int n = form.size();
    std::copy(y, y + n, y_.begin());
    for (int j = 0; j < n; ++j) {
      const auto u = static_cast<std::size_t>(j);
      const double step =
          std::cbrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(y[j]));
      y_[u] = y[j] + step;
      form.rhs(context, y_.data(), plus_.data(), scratch);
      y_[u] = y[j] - step;
      form.rhs(context, y_.data(), minus_.data(), scratch);
      y_[u] = y[j];
      for (int i = 0; i < n; ++i) {
        const auto v = static_cast<std::size_t>(i);
        jacobian(i, j) = (plus_[v] - minus_[v]) / (2.0 * step);
      }
    }
  }

  mutable long calls = 0;

 private:
  mutable std::vector<double> y_, plus_, minus_;
};

double max_difference(const ReferenceRun& a, const ReferenceRun& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < a.trajectory.states.size(); ++k) {
    const core::BodyState& x = a.trajectory.states[k][0];
    const core::BodyState& y = b.trajectory.states[k][0];
    d = std::max({d, (x.p_WBr - y.p_WBr).norm(), (x.w_WB_B - y.w_WB_B).norm(),
                  rotation::geodesic_angle(x.theta_WB, y.theta_WB)});
  }
  return d;
}

}  // namespace

TEST_CASE("CVODE and IDA use a user Jacobian and reach the same solution",
          "[cvode][ida][jacobian]") {
  // coulomb_wall over 10 s (configuration-dependent forces: a Jacobian with real coupling).
  const core::Model model = testing::coulomb_wall();
  const std::vector<double> times = core::output_times(10.0, 0.1);
  const OdeForm form(model);
  const CentralDifferenceJacobian jacobian(form.size());
  SolverOptions own;
  own.rtol = 1e-10;
  own.cvode_method = CvodeMethod::kBdf;  // Newton with the iteration matrix in every step
  SolverOptions hooked = own;
  hooked.jacobian = &jacobian;
  SolverOptions tight = own;
  tight.rtol = 1e-12;
  for (auto solve : {&solve_cvode, &solve_ida}) {
    jacobian.calls = 0;
    const ReferenceRun with_own = solve(model, times, own);
    const ReferenceRun with_hook = solve(model, times, hooked);
    const ReferenceRun reference = solve(model, times, tight);
    CAPTURE(with_own.solver, jacobian.calls, with_hook.stats.jacobian_evaluations,
            with_own.stats.rhs_evaluations, with_hook.stats.rhs_evaluations);
    // The hook is what the solver called for every iteration matrix it built.
    CHECK(jacobian.calls == with_hook.stats.jacobian_evaluations);
    CHECK(jacobian.calls > 0);
    // Its own difference quotients cost n = 13 evaluations per matrix; with the hook the
    // solver spends none of them (the hook's own evaluations are not the solver's).
    CHECK(with_hook.stats.rhs_evaluations <
          with_own.stats.rhs_evaluations - 13 * with_own.stats.jacobian_evaluations / 2);
    // Another Newton matrix changes the iterates within the nonlinear tolerance, hence the
    // step sequence a little: the two solutions differ by at most about one run's error (each
    // checked against rtol 1e-12): allow 3 × the larger error. Measured: CVODE bit for bit (its
    // Newton corrections are ~1e-12, so the matrices' ~1e-8 relative difference acts below
    // round-off), IDA 0.27×.
    const double between = max_difference(with_own, with_hook);
    const double error =
        std::max(max_difference(with_own, reference), max_difference(with_hook, reference));
    CAPTURE(between, error);
    CHECK(between <= 3.0 * error);
  }
}

}  // namespace flexref::reference
