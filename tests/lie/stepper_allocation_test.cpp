/// step() allocates nothing: the global operator new is replaced in this test program and
/// counts allocations while a flag is set around the calls to step().
#include <atomic>
#include <catch2/catch.hpp>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <string>

#include "lie/stepper.hpp"
#include "tests/lie/test_problems.hpp"

namespace {

std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};

void* counted_allocation(std::size_t size, std::size_t alignment) noexcept {
  if (g_counting.load()) ++g_allocations;
  if (size == 0) size = 1;
  if (alignment <= alignof(std::max_align_t)) return std::malloc(size);
  return std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
}

void* checked(void* p) {
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

// Every replaceable form is replaced, so that allocation and deallocation always pair
// malloc/free (a sanitizer's own operator new[] must not meet this free). Not inlined: GCC
// would otherwise warn that free() receives a pointer from operator new, which is true and
// intended here.
[[gnu::noinline]] void release(void* p) noexcept { std::free(p); }

}  // namespace

void* operator new(std::size_t n) { return checked(counted_allocation(n, 1)); }
void* operator new[](std::size_t n) { return checked(counted_allocation(n, 1)); }
void* operator new(std::size_t n, std::align_val_t a) {
  return checked(counted_allocation(n, static_cast<std::size_t>(a)));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return checked(counted_allocation(n, static_cast<std::size_t>(a)));
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return counted_allocation(n, 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return counted_allocation(n, 1);
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_allocation(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_allocation(n, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { release(p); }

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
