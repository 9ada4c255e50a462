#include "reference/dae_form.hpp"

#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <vector>

#include "reference/ode_form.hpp"
#include "tests/support/test_models.hpp"

namespace flexref::core {
namespace {

// The DAE residual at the consistent initial values (y, y' built from the ODE form's
// accelerations) must vanish: this ties the DAE form (M times the accelerations minus the loads,
// Model::dynamics_residual) to the quasi-velocity form (the accelerations solved for). Round-off:
// residual rows are sums of O(|I||ω|²) ≈ 1e4 terms for the heavy top (ω = 150) → 1e4·1e-16·few ≈
// 1e-11; relative to the row scale we accept 1e-12.
double max_residual(const Model& model, double t) {
  const reference::DaeForm dae(model);
  reference::DaeForm::Scratch scratch = dae.make_scratch();
  const auto n = static_cast<std::size_t>(dae.size());
  std::vector<double> y(n), yp(n), res(n);
  const LoadContext ctx{t, t};
  dae.initial_values(ctx, model.initial_state(), y.data(), yp.data());
  dae.residual(ctx, y.data(), yp.data(), res.data(), scratch);
  double m = 0.0;
  for (double r : res) m = std::max(m, std::abs(r));
  return m;
}

TEST_CASE("DAE residual vanishes at consistent values from the ODE form", "[core]") {
  // max_residual's round-off, derived above it: 1e-12 of the rows' scale.
  CHECK(max_residual(testing::coulomb_wall_model(), 0.0) < 1e-12);
  CHECK(max_residual(testing::loaded_free_body_model(), 0.05) < 1e-12);
  // Heavy top: angular-momentum rows of size I·ω² ≈ 15·150·4.6 ≈ 1e4.
  CHECK(max_residual(testing::heavy_top_model(), 0.0) < 1e-12 * 1e4);
}

TEST_CASE("DAE residual detects a wrong acceleration", "[core]") {
  // Perturb ω̄̇₁: the rotation rows must react with the inertia I₁ = 0.4 kg·m² (residual
  // 0.4 · 1e-3 = 4e-4), i.e. the check above is not vacuous.
  const Model model = testing::coulomb_wall_model();
  const reference::DaeForm dae(model);
  reference::DaeForm::Scratch scratch = dae.make_scratch();
  const auto n = static_cast<std::size_t>(dae.size());
  std::vector<double> y(n), yp(n), res(n);
  dae.initial_values({0, 0}, model.initial_state(), y.data(), yp.data());
  const int w = dae.blocks()[0].w;
  yp[static_cast<std::size_t>(w)] += 1e-3;
  dae.residual({0, 0}, y.data(), yp.data(), res.data(), scratch);
  CHECK(std::abs(res[static_cast<std::size_t>(w)]) == Approx(0.4e-3).epsilon(1e-6));
}

TEST_CASE("DAE form has the ODE form's layout", "[core]") {
  // A Jacobian of the ODE right-hand side serves IDA (reference/ode_jacobian.hpp) only if the
  // two forms order y alike: pivot [θ ω̄] = 7, free [p θ v ω̄] = 13.
  for (const Model& model : {testing::heavy_top_model(), testing::coulomb_wall_model()}) {
    const reference::DaeForm dae(model);
    const reference::OdeForm ode(model);
    REQUIRE(dae.size() == ode.size());
    for (std::size_t i = 0; i < dae.blocks().size(); ++i) {
      const auto& d = dae.blocks()[i];
      const auto& o = ode.blocks()[i];
      CHECK(d.p == o.p);
      CHECK(d.theta == o.theta);
      CHECK(d.v == o.v);
      CHECK(d.w == o.w);
      CHECK(d.q == o.q);
      CHECK(d.qd == o.qd);
    }
  }
}

TEST_CASE("DAE mass rows are dF/dy'", "[core]") {
  // F is linear in y': each column of P equals the residual's change under a unit change of
  // y'_j, divided by it (δ = 1: exact up to the rounding of F, |F| ≈ 10 → 1e-14).
  const Model model = testing::loaded_free_body_model();
  const reference::DaeForm dae(model);
  reference::DaeForm::Scratch scratch = dae.make_scratch();
  const auto n = static_cast<std::size_t>(dae.size());
  std::vector<double> y(n), yp(n), r0(n), r1(n);
  const LoadContext ctx{0.05, 0.05};
  dae.initial_values(ctx, model.initial_state(), y.data(), yp.data());
  Eigen::MatrixXd mass(dae.size(), dae.size());
  dae.mass_rows(ctx, y.data(), mass, scratch);
  dae.residual(ctx, y.data(), yp.data(), r0.data(), scratch);
  for (std::size_t j = 0; j < n; ++j) {
    yp[j] += 1.0;
    dae.residual(ctx, y.data(), yp.data(), r1.data(), scratch);
    yp[j] -= 1.0;
    for (std::size_t i = 0; i < n; ++i) {
      CAPTURE(i, j);
      CHECK(mass(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) ==
            Approx(r1[i] - r0[i]).margin(1e-13));
    }
  }
}

TEST_CASE("DAE unpack recovers the state", "[core]") {
  const Model model = testing::loaded_free_body_model();
  const reference::DaeForm dae(model);
  const auto n = static_cast<std::size_t>(dae.size());
  std::vector<double> y(n), yp(n);
  const State s0 = model.initial_state();
  dae.initial_values({0, 0}, s0, y.data(), yp.data());
  State s = s0;
  dae.unpack(0.0, y.data(), s);
  // ω̄ is a component of y: exact.
  CHECK(s[0].w_WB_B == s0[0].w_WB_B);
  CHECK((s[0].p_WBr - s0[0].p_WBr).norm() == 0.0);
}

TEST_CASE("ODE form pack/unpack round trip and normalization", "[core]") {
  const Model model = testing::heavy_top_model();
  const reference::OdeForm ode(model);
  REQUIRE(ode.size() == 7);
  std::vector<double> y(7);
  State s = model.initial_state();
  ode.pack(s, y.data());
  y[0] *= 1.5;  // off the sphere
  ode.normalize_euler_parameters(y.data());
  CHECK(std::hypot(std::hypot(y[0], y[1]), std::hypot(y[2], y[3])) == Approx(1.0).epsilon(1e-15));
  ode.unpack(0.0, y.data(), s);
  CHECK(s[0].p_WBr == model.initial_state()[0].p_WBr);  // pivot stays put
}

}  // namespace
}  // namespace flexref::core
