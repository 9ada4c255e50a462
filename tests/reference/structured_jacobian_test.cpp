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
#include "tests/support/jacobian_models.hpp"
#include "tests/support/test_models.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// A random y: positions and velocities O(1), θ random of norm 1.2, modal coordinates O(0.05),
/// their rates O(0.3).
std::vector<double> random_y(const OdeForm& form, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  std::vector<double> y(static_cast<std::size_t>(form.size()));
  for (double& v : y) v = normal(rng);
  for (const OdeForm::Block& k : form.blocks()) {
    if (k.theta >= 0) {
      Eigen::Map<Eigen::Vector4d> theta(y.data() + k.theta);
      theta *= 1.2 / theta.norm();
    }
    for (int i = 0; i < k.n; ++i) {
      y[static_cast<std::size_t>(k.q + i)] *= 0.05;
      y[static_cast<std::size_t>(k.qd + i)] *= 0.3;
    }
  }
  if (form.work_index() >= 0) y[static_cast<std::size_t>(form.work_index())] = 0.0;
  return y;
}

/// Largest condition number of the bodies' mass matrices at y, over the rows each body solves
/// for (free: all; pivot: rotation and modes; prescribed: modes). Flexible: the dense (6+n)²
/// matrix; rigid: diag(m, I_Br).
double mass_condition(const OdeForm& form, const std::vector<double>& y, double t) {
  core::State state = form.model().initial_state();
  form.unpack(t, y.data(), state);
  double kappa = 1.0;
  for (int i = 0; i < form.model().num_bodies(); ++i) {
    const core::Body& b = form.model().body(i);
    const int n = b.mode_count();
    const int known = b.is_free() ? 0 : (b.is_prescribed() ? 6 : 3);
    if (known == 6 && n == 0) continue;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6 + n, 6 + n);
    if (b.is_flexible()) {
      const core::BodyState& s = state[static_cast<std::size_t>(i)];
      flexible::flexible_mass_matrix(b.invariants(), rotation::rotation_matrix(s.theta_WB), s.q_f,
                                     M);
    } else {
      M.topLeftCorner<3, 3>() = b.mass() * Eigen::Matrix3d::Identity();
      M.bottomRightCorner<3, 3>() = b.I_Br_B();
    }
    const Eigen::MatrixXd U = M.bottomRightCorner(6 + n - known, 6 + n - known);
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(U).eigenvalues();
    kappa = std::max(kappa, lambda.maxCoeff() / lambda.minCoeff());
  }
  return kappa;
}

/// Per column c of y: E = (4 D(h/2) − D(h)) / 3 from central differences D of the right-hand
/// side with h = 1e-3 max(1, |y_c|). Bound: |D(h) − D(h/2)| (it bounds E's O(h⁴) truncation
/// while c h² ≫ h⁴) + 3 ε_f / h (E's rounding, ε_f the rounding of one evaluation: a solve
/// with M, ≤ 4 d κ(M) ε S_f with d = dim y terms of scale S_f = max |f| + 1, Higham Thm. 10.4)
/// + 4 ε_f / h_J (J's own central differences of the loads with h_J = ε^{1/3}: their rounding
/// mapped through M⁻¹; their truncation, (h_J/h)² |D(h) − D(h/2)|, is below the first term).
/// Returns the largest ratio |J − E| / bound over the entries (≤ 1 passes); `wrong` flips the
/// sign of J's column before the comparison.
double worst_ratio(const core::Model& model, double t, unsigned seed, int wrong = -1) {
  const OdeForm form(model);
  OdeForm::Scratch scratch = form.make_scratch();
  const StructuredJacobian jacobian(form);
  StructuredJacobian::Scratch jac_scratch = jacobian.make_scratch();
  std::mt19937 rng(seed);
  const std::vector<double> y = random_y(form, rng);
  const core::LoadContext context{t, t};
  const int d = form.size();
  Eigen::MatrixXd J(d, d);
  jacobian.evaluate(context, y.data(), J, jac_scratch);
  if (wrong >= 0) J.col(wrong) *= -1.0;

  Eigen::VectorXd f(d);
  form.rhs(context, y.data(), f.data(), scratch);
  const double S_f = f.cwiseAbs().maxCoeff() + 1.0;
  const double eps_f = 4.0 * d * mass_condition(form, y, t) * kEps * S_f;
  const double h_J = std::cbrt(kEps);
  double worst = 0.0;
  for (int c = 0; c < d; ++c) {
    const double h = 1e-3 * std::max(1.0, std::abs(y[static_cast<std::size_t>(c)]));
    const auto D = [&](double step) {
      std::vector<double> yp = y, ym = y;
      yp[static_cast<std::size_t>(c)] += step;
      ym[static_cast<std::size_t>(c)] -= step;
      Eigen::VectorXd fp(d), fm(d);
      form.rhs(context, yp.data(), fp.data(), scratch);
      form.rhs(context, ym.data(), fm.data(), scratch);
      return Eigen::VectorXd((fp - fm) / (2.0 * step));
    };
    const Eigen::VectorXd D1 = D(h), D2 = D(h / 2.0);
    const Eigen::VectorXd E = (4.0 * D2 - D1) / 3.0;
    const double bound = (D1 - D2).cwiseAbs().maxCoeff() + 3.0 * eps_f / h + 4.0 * eps_f / h_J;
    // Not vacuous: the bound is 1e-4 of the column's scale at most.
    CHECK(bound <= 1e-4 * (E.cwiseAbs().maxCoeff() + S_f));
    worst = std::max(worst, (J.col(c) - E).cwiseAbs().maxCoeff() / bound);
  }
  return worst;
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
  const std::vector<double> y = random_y(form, rng);
  Eigen::MatrixXd J(form.size(), form.size());
  const core::LoadContext context{0.25, 0.25};
  jacobian.evaluate(context, y.data(), J, scratch);
  CHECK(testing::count_allocations([&] { jacobian.evaluate(context, y.data(), J, scratch); }) == 0);
  CHECK(J.allFinite());
  CHECK(jacobian.tangent_size() == form.size() - 2 - 1);  // two θ (4 → 3), no W_d column
}

}  // namespace
}  // namespace flexref::reference
