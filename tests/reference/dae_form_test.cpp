#include "reference/dae_form.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "reference/ode_form.hpp"
#include "tests/support/test_models.hpp"

namespace flexref::core {
namespace {

// The DAE residual at the consistent initial values (y, y' built from the ODE form's
// accelerations) must vanish: this ties the DAE form (θ rows premultiplied by 2Ḡᵀ, GGL terms)
// to the quasi-velocity form. Round-off: residual rows are sums of O(|I||ω|²) ≈ 1e4 terms for
// the heavy top (ω = 150) → 1e4·1e-16·few ≈ 1e-11; relative to the row scale we accept 1e-12.
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
  CHECK(max_residual(testing::coulomb_wall_model(), 0.0) < 1e-12);
  CHECK(max_residual(testing::loaded_free_body_model(), 0.05) < 1e-12);
  // Heavy top: angular-momentum rows of size I·ω² ≈ 15·150·4.6 ≈ 1e4.
  CHECK(max_residual(testing::heavy_top_model(), 0.0) < 1e-12 * 1e4);
}

TEST_CASE("DAE residual detects a wrong acceleration", "[core]") {
  // Perturb one component of v̇_θ tangent to the sphere: the θ rows must react with the
  // inertia, i.e. the check above is not vacuous.
  const Model model = testing::coulomb_wall_model();
  const reference::DaeForm dae(model);
  reference::DaeForm::Scratch scratch = dae.make_scratch();
  const auto n = static_cast<std::size_t>(dae.size());
  std::vector<double> y(n), yp(n), res(n);
  dae.initial_values({0, 0}, model.initial_state(), y.data(), yp.data());
  yp[10 + 1] += 1e-3;  // v̇_θ, component e1 (identity attitude: tangent direction)
  dae.residual({0, 0}, y.data(), yp.data(), res.data(), scratch);
  double m = 0.0;
  for (double r : res) m = std::max(m, std::abs(r));
  CHECK(m > 1e-4);
}

TEST_CASE("DAE differential ids mark λ and μ algebraic", "[core]") {
  const Model model = testing::heavy_top_model();  // pivot: [θ v_θ λ μ] = 10
  const reference::DaeForm dae(model);
  REQUIRE(dae.size() == 10);
  const std::vector<double> ids = dae.differential_ids();
  for (int i = 0; i < 8; ++i) CHECK(ids[static_cast<std::size_t>(i)] == 1.0);
  CHECK(ids[8] == 0.0);
  CHECK(ids[9] == 0.0);
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
  // ω̄ = 2Ḡ(½Ḡᵀω̄) = ω̄ since ḠḠᵀ = I: a few ulp of |ω| ≈ 4.
  CHECK((s[0].w_WB_B - s0[0].w_WB_B).norm() < 1e-14);
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
