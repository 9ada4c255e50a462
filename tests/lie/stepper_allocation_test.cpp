/// step() allocates nothing: the global operator new is replaced in this test program and
/// counts allocations while a flag is set around the calls to step().
#include <atomic>
#include <catch2/catch.hpp>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <string>

#include "lie/stepper.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/test_problems.hpp"

namespace {
using flexref::testing::g_allocations;
using flexref::testing::g_counting;
}  // namespace

namespace flexref::lie {
namespace {

TEST_CASE("step() allocates nothing", "[lie][conformance][allocation]") {
  // A free body across a load discontinuity (restart path), a pivot body, and configuration-
  // and velocity-dependent loads.
  const core::Model book = testing::book_toss_step();
  const core::Model top = testing::heavy_top();
  const core::Model wall = testing::damped_coulomb_wall();
  // The hybrid scheme (LTE): a free flexible body under its torque pulse, and a prescribed
  // rotating beam.
  const core::Model spinner = testing::flexible_spinner_model(core::FlexibleFormulation::kLte);
  const core::Model cantilever =
      testing::rotating_cantilever_model(core::FlexibleFormulation::kLte, 3.0);
  for (const core::Model* model : {&book, &top, &wall, &spinner, &cantilever}) {
    for (const std::string& name : builtin_scheme_names()) {
      const auto stepper = make_stepper(name, *model, {});
      stepper->initialize(0.0, model->initial_state());
      g_allocations = 0;
      g_counting = true;
      bool ok = true;
      for (int n = 0; n < 200; ++n) ok = stepper->step(1e-3).ok && ok;  // crosses t = 0.1
      g_counting = false;
      INFO("scheme " << name << ", body " << model->body(0).name());
      CHECK(ok);
      CHECK(g_allocations.load() == 0);
    }
  }
}

TEST_CASE("genalpha: step() allocates nothing", "[lie][conformance][allocation]") {
  // Rigid bodies across a load discontinuity (restart), a pivot, configuration- and
  // velocity-dependent loads, Andrews' squeezer (ideal joints, index 3), a free flexible body
  // (coupled model) and a prescribed one (LTE).
  const core::Model book = testing::book_toss_step();
  const core::Model top = testing::heavy_top();
  const core::Model wall = testing::damped_coulomb_wall();
  const scene::Scene andrews = scene::read_scene("scenes/andrews_squeezer.toml");
  const core::Model spinner = testing::flexible_spinner_model(core::FlexibleFormulation::kCoupled);
  const core::Model cantilever =
      testing::rotating_cantilever_model(core::FlexibleFormulation::kLte, 3.0);
  for (const core::Model* model :
       {&book, &top, &wall, static_cast<const core::Model*>(andrews.model.get()), &spinner,
        &cantilever}) {
    const auto stepper = make_stepper("genalpha", *model, {});
    stepper->initialize(0.0, model->initial_state());
    const double h = model->has_constraints() ? 1e-4 : 1e-3;
    // The first step orders the iteration matrix's pattern and factors it (KLU allocates its
    // factors once per pattern, lie/sparse_lu.hpp); the steps after it reassemble and refactor
    // in place, also where h changes (steps 100 to 149 at h/2: two reassemblies).
    bool ok = stepper->step(h).ok;
    g_allocations = 0;
    g_counting = true;
    long first = -1;
    for (int n = 1; n < 200; ++n) {
      ok = stepper->step(n >= 100 && n < 150 ? 0.5 * h : h).ok && ok;  // crosses t = 0.1 (book)
      if (first < 0 && g_allocations.load() > 0) first = n;
    }
    g_counting = false;
    INFO("genalpha, body " << model->body(0).name() << " first at step " << first);
    CHECK(ok);
    CHECK(g_allocations.load() == 0);
  }
}

TEST_CASE("the allocation counter counts", "[lie][allocation]") {
  // The check above is only meaningful if allocations in this program are seen.
  g_allocations = 0;
  g_counting = true;
  auto* p = new std::string(100, 'x');
  g_counting = false;
  delete p;
  CHECK(g_allocations.load() >= 1);
}

}  // namespace
}  // namespace flexref::lie
