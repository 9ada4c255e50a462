/// Tests of reference/ode_jacobian: J = ∂f/∂y of the ODE form against Richardson-extrapolated
/// central differences of OdeForm::rhs at random states (θ off the unit sphere, so the radial
/// direction is tested too), for rigid free and pivot bodies, a free flexible body (coupled and
/// LTE, with modal damping: the dissipated-work row) coupled to a rigid body by a
/// configuration- and velocity-dependent tether (loads across bodies), a pivot flexible body
/// under gravity and prescribed flexible bodies (constant rate, and a spin-up law whose α̅ is
/// not zero). The comparison fails on a wrong sign; the evaluation allocates nothing.
#include "reference/structured_jacobian.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "core/gravity.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "reference/ode_form.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/jacobian_check.hpp"
#include "tests/support/jacobian_models.hpp"
#include "tests/support/test_models.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

/// J at a random state (testing::random_y) against differences of the right-hand side
/// (testing::worst_jacobian_ratio: ≤ 1 passes); `wrong` flips the sign of J's column first.
double worst_ratio(const core::Model& model, double t, unsigned seed, int wrong = -1) {
  const OdeForm form(model);
  const StructuredJacobian jacobian(form);
  StructuredJacobian::Scratch jac_scratch = jacobian.make_scratch();
  std::mt19937 rng(seed);
  const std::vector<double> y = testing::random_y(form, rng);
  const core::LoadContext context{t, t};
  Eigen::MatrixXd J(form.size(), form.size());
  jacobian.evaluate(context, y.data(), J, jac_scratch);
  if (wrong >= 0) J.col(wrong) *= -1.0;
  return testing::worst_jacobian_ratio(form, context, y, J);
}

TEST_CASE("the ODE Jacobian of rigid bodies equals differences of the right-hand side",
          "[reference][jacobian]") {
  CHECK(worst_ratio(testing::loaded_free_body_model(), 0.05, 1) <= 1.0);
  CHECK(worst_ratio(testing::damped_coulomb_wall(), 0.05, 2) <= 1.0);
  CHECK(worst_ratio(testing::heavy_top_model(), 0.05, 3) <= 1.0);
}

TEST_CASE("the ODE Jacobian of flexible bodies equals differences of the right-hand side",
          "[reference][jacobian]") {
  for (const core::FlexibleFormulation formulation :
       {core::FlexibleFormulation::kCoupled, core::FlexibleFormulation::kLte}) {
    INFO(core::to_string(formulation));
    CHECK(worst_ratio(testing::spinner_and_block(formulation), 0.25, 11) <= 1.0);
    CHECK(worst_ratio(testing::pivot_spinner(formulation), 0.25, 12) <= 1.0);
    CHECK(worst_ratio(testing::rotating_cantilever_model(formulation, 3.0, 4), 0.7, 13) <= 1.0);
    CHECK(worst_ratio(testing::spin_up_beam_model(formulation, 2.0, 4), 3.0, 14) <= 1.0);
  }
}

TEST_CASE("the ODE Jacobian check catches a wrong sign", "[reference][jacobian]") {
  // Columns: the spinner's θ (e1), ω̄ (y), a modal coordinate, a modal rate; the block's v.
  const core::Model model = testing::spinner_and_block(core::FlexibleFormulation::kCoupled);
  const OdeForm form(model);
  const OdeForm::Block& s = form.blocks()[0];
  const OdeForm::Block& b = form.blocks()[1];
  for (const int column : {s.theta + 1, s.w + 1, s.q + 2, s.qd + 3, b.v}) {
    INFO("column " << column);
    CHECK(worst_ratio(model, 0.25, 11, column) > 100.0);
  }
}

TEST_CASE("the ODE Jacobian allocates nothing", "[reference][jacobian]") {
  const core::Model model = testing::spinner_and_block(core::FlexibleFormulation::kCoupled);
  const OdeForm form(model);
  const StructuredJacobian jacobian(form);
  StructuredJacobian::Scratch scratch = jacobian.make_scratch();
  std::mt19937 rng(5);
  const std::vector<double> y = testing::random_y(form, rng);
  Eigen::MatrixXd J(form.size(), form.size());
  const core::LoadContext context{0.25, 0.25};
  jacobian.evaluate(context, y.data(), J, scratch);
  CHECK(testing::count_allocations([&] { jacobian.evaluate(context, y.data(), J, scratch); }) == 0);
  CHECK(J.allFinite());
  // Two θ (4 → 3), no column for the integrals (W_d, and W_a of the block's applied force).
  CHECK(jacobian.tangent_size() == form.size() - 2 - form.integral_count());
}

}  // namespace
}  // namespace flexref::reference
