/// Evaluations allocate nothing: the ODE right-hand side, the DAE residual, the loads and the
/// energy, on models with every force element kind. The global operator new of this program
/// counts allocations (tests/support/allocation_counting.hpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "reference/dae_form.hpp"
#include "reference/ode_form.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/test_models.hpp"

namespace flexref::core {
namespace {

TEST_CASE("model evaluations allocate nothing", "[core][allocation]") {
  const Model wall = testing::coulomb_wall_model();
  const Model top = testing::heavy_top_model();
  const Model loaded = testing::loaded_free_body_model();
  for (const Model* model : {&wall, &top, &loaded}) {
    const reference::OdeForm ode(*model);
    reference::OdeForm::Scratch ode_scratch = ode.make_scratch();
    const reference::DaeForm dae(*model);
    reference::DaeForm::Scratch dae_scratch = dae.make_scratch();
    std::vector<double> y(static_cast<std::size_t>(ode.size())), f(y.size());
    std::vector<double> z(static_cast<std::size_t>(dae.size())), zp(z.size()), r(z.size());
    const State s = model->initial_state();
    ode.pack(s, y.data());
    const LoadContext ctx{0.05, 0.05};
    dae.initial_values(ctx, s, z.data(), zp.data());
    Workspace ws = model->make_workspace();
    Accelerations acc = model->make_accelerations();
    double energy = 0.0;
    const long n = testing::count_allocations([&] {
      ode.rhs(ctx, y.data(), f.data(), ode_scratch);
      dae.residual(ctx, z.data(), zp.data(), r.data(), dae_scratch);
      model->compute_accelerations(ctx, s, ws, acc);
      energy = model->kinetic_energy(s) + model->potential_energy(ctx, s, ws);
    });
    CHECK(std::isfinite(energy));
    INFO("model with body " << model->body(0).name());
    CHECK(n == 0);
  }
}

TEST_CASE("the allocation counter counts", "[core][allocation]") {
  // The check above could not fail if the counter were broken: it must see operator new and,
  // where it can (glibc, no AddressSanitizer), Eigen's heap matrices, which use malloc.
  std::size_t size = 0;
  const long n = testing::count_allocations([&] {
    std::vector<double> v(10);
    size = v.size();
  });
  CHECK(size == 10);
  CHECK(n >= 1);
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
  double sum = 0.0;
  const long m = testing::count_allocations([&] {
    const Eigen::MatrixXd a = Eigen::MatrixXd::Constant(5, 5, 1.0);
    sum = a.sum();
  });
  CHECK(sum == 25.0);
  CHECK(m >= 1);
#endif
}

}  // namespace
}  // namespace flexref::core
