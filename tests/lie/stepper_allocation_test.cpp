/// step() allocates nothing: the global operator new is replaced in this test program and
/// counts allocations while a flag is set around the calls to step().
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <string>

#include <catch2/catch.hpp>

#include "lie/stepper.hpp"
#include "tests/lie/test_problems.hpp"

namespace {

std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};

void* counted_allocation(std::size_t size, std::size_t alignment) {
  if (g_counting.load()) ++g_allocations;
  const std::size_t rounded = (size + alignment - 1) / alignment * alignment;
  void* p = alignment <= alignof(std::max_align_t) ? std::malloc(size == 0 ? 1 : size)
                                                   : std::aligned_alloc(alignment, rounded);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

void* operator new(std::size_t size) { return counted_allocation(size, 1); }
void* operator new(std::size_t size, std::align_val_t alignment) {
  return counted_allocation(size, static_cast<std::size_t>(alignment));
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace flexref::lie {
namespace {

TEST_CASE("step() allocates nothing", "[lie][conformance][allocation]") {
  // A free body across a load discontinuity (restart path), a pivot body, and configuration-
  // and velocity-dependent loads.
  const core::Model book = testing::book_toss_step();
  const core::Model top = testing::heavy_top();
  const core::Model wall = testing::damped_coulomb_wall();
  for (const core::Model* model : {&book, &top, &wall}) {
    for (const std::string& name : scheme_names()) {
      const auto stepper = make_stepper(name, *model);
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
