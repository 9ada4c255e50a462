/// Evaluations allocate nothing: the ODE right-hand side, the DAE residual, the loads and the
/// energy, on models with every force element kind. The global operator new of this program
/// counts allocations (tests/support/allocation_counting.hpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "contact/contact.hpp"
#include "contact/gap_support.hpp"
#include "core/applied_load.hpp"
#include "core/impact_counter.hpp"
#include "reference/dae_form.hpp"
#include "reference/ode_form.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/node_contact_models.hpp"
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

TEST_CASE("node contacts, gap supports, wear channels and impact counts allocate nothing",
          "[core][allocation]") {
  // The stiff particle in contact with a plane at its node (named: a wear channel), a gap
  // support on the same node, a harmonic force there (applied work tracked).
  RigidBodyDescription d = testing::stiff_particle_body("p", 1.0, 0.01, 1.0, 1e6);
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, 0.05);
  d.initial.v_WBo = Eigen::Vector3d(0.3, 0.1, -0.5);
  const NodeAttachment node = testing::node_of(d, 0);
  contact::ContactPair pair = contact::ContactPair::sphere_plane(
      0, Eigen::Vector3d::Zero(), 0.1, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  pair.node_b = node;
  contact::FrictionLaw friction;
  friction.mu = 0.3;
  contact::GapSupportGeometry gap;
  gap.clearance = 0.01;
  gap.p_WS = Eigen::Vector3d(0.0, 0.02, 0.0);
  std::vector<std::unique_ptr<const ForceElement>> elements;
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{pair},
      contact::NormalLaw::hunt_crossley(1e6, 1.5, 0.5, 1.0), friction, 1.0, "floor"));
  elements.push_back(std::make_unique<contact::GapSupport>(
      0, Eigen::Vector3d::Zero(), node, gap, contact::NormalLaw::hunt_crossley(1e6, 1.5, 0.5, 1.0),
      friction, 1.0, "support"));
  elements.push_back(std::make_unique<AppliedForce>(0, Eigen::Vector3d(0.0, 1.0, 0.0),
                                                    LoadFrame::kWorld, Eigen::Vector3d::Zero(),
                                                    TimeProfile::harmonic(3.0, 0.0), node));
  std::vector<Body> bodies;
  bodies.emplace_back(d);
  const Model model(std::move(bodies), std::move(elements));
  REQUIRE(model.extra_integral_count() == 3);  // applied work, two wear works
  const reference::OdeForm ode(model);
  reference::OdeForm::Scratch ode_scratch = ode.make_scratch();
  const reference::DaeForm dae(model);
  reference::DaeForm::Scratch dae_scratch = dae.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(ode.size())), f(y.size());
  std::vector<double> z(static_cast<std::size_t>(dae.size())), zp(z.size()), r(z.size());
  State s = model.initial_state();
  s[0].q_f = Eigen::Vector3d(0.001, 0.002, -0.003);
  s[0].qd_f = Eigen::Vector3d(0.1, -0.2, 0.3);
  ode.pack(s, y.data());
  const LoadContext ctx{0.05, 0.05};
  dae.initial_values(ctx, s, z.data(), zp.data());
  Workspace ws = model.make_workspace();
  ImpactCounter impacts(model);
  impacts.start(ctx, s, ws);
  std::vector<double> rates(4);
  const long n = testing::count_allocations([&] {
    ode.rhs(ctx, y.data(), f.data(), ode_scratch);
    dae.residual(ctx, z.data(), zp.data(), r.data(), dae_scratch);
    model.wear_samples(ctx, s, ws);
    model.integral_rates(ctx, s, ws, rates);
    impacts.update(ctx, s, ws);
    impacts.update_at_root(ctx, s, ws);
  });
  CHECK(n == 0);
  // Both contacts are engaged: friction does wear work in both channels.
  CHECK(rates[2] > 0.0);
  CHECK(rates[3] > 0.0);
}

TEST_CASE("worn contacts and their depth rates allocate nothing", "[core][allocation]") {
  // The node contact and the gap support of the case above with wear laws: a pin (Archard) and
  // a worn hole of 8 sectors (work rate), their depths states of the model.
  RigidBodyDescription d = testing::stiff_particle_body("p", 1.0, 0.01, 1.0, 1e6);
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, 0.05);
  d.initial.v_WBo = Eigen::Vector3d(0.3, 0.1, -0.5);
  const NodeAttachment node = testing::node_of(d, 0);
  contact::ContactPair pair = contact::ContactPair::sphere_plane(
      0, Eigen::Vector3d::Zero(), 0.1, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  pair.node_b = node;
  contact::FrictionLaw friction;
  friction.mu = 0.3;
  contact::GapSupportGeometry gap;
  gap.clearance = 0.01;
  gap.p_WS = Eigen::Vector3d(0.0, 0.02, 0.0);
  WearLaw pin;
  pin.kind = WearLaw::Kind::kArchard;
  pin.coefficient = 1e-4;
  pin.hardness = 1e9;
  pin.area = 1e-6;
  pin.initial_depth = {1e-4};
  WearLaw hole;
  hole.kind = WearLaw::Kind::kWorkRate;
  hole.coefficient = 1e-12;
  hole.sectors = 8;
  hole.thickness = 0.01;
  hole.radius = 0.02;
  hole.initial_depth = {1e-4, 2e-4, 0.0, 5e-5, 0.0, 0.0, 3e-4, 1e-4};
  std::vector<std::unique_ptr<const ForceElement>> elements;
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{pair},
      contact::NormalLaw::hunt_crossley(1e6, 1.5, 0.5, 1.0), friction, 1.0, "floor", pin));
  elements.push_back(std::make_unique<contact::GapSupport>(
      0, Eigen::Vector3d::Zero(), node, gap, contact::NormalLaw::hunt_crossley(1e6, 1.5, 0.5, 1.0),
      friction, 1.0, "support", hole));
  std::vector<Body> bodies;
  bodies.emplace_back(d);
  const Model model(std::move(bodies), std::move(elements));
  REQUIRE(model.wear_depth_count() == 9);
  const reference::OdeForm ode(model);
  reference::OdeForm::Scratch ode_scratch = ode.make_scratch();
  const reference::DaeForm dae(model);
  reference::DaeForm::Scratch dae_scratch = dae.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(ode.size())), f(y.size());
  std::vector<double> z(static_cast<std::size_t>(dae.size())), zp(z.size()), r(z.size());
  State s = model.initial_state();
  s[0].q_f = Eigen::Vector3d(0.001, 0.002, -0.003);
  s[0].qd_f = Eigen::Vector3d(0.1, -0.2, 0.3);
  ode.pack(s, y.data());
  const LoadContext ctx{0.05, 0.05};
  dae.initial_values(ctx, s, z.data(), zp.data());
  Workspace ws = model.make_workspace();
  std::vector<double> rates(9);
  double volume = 0.0;
  const long n = testing::count_allocations([&] {
    ode.rhs(ctx, y.data(), f.data(), ode_scratch);
    dae.residual(ctx, z.data(), zp.data(), r.data(), dae_scratch);
    model.wear_depth_rates(ctx, s, ws, rates);
    volume = model.wear_volume(0, s) + model.wear_volume(1, s);
  });
  CHECK(n == 0);
  CHECK(volume > 0.0);
  // The pin wears (it penetrates the floor).
  CHECK(rates[0] > 0.0);
  // The depths' rows of the ODE form are the rates.
  for (int k = 0; k < 9; ++k) {
    CHECK(f[static_cast<std::size_t>(ode.depth_index() + k)] == rates[static_cast<std::size_t>(k)]);
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
