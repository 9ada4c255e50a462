#pragma once
/// \file allocation_counting.hpp
/// Replaces the global operator new/delete of a test program with versions that count
/// allocations while `flexref::testing::g_counting` is set. Include in exactly ONE
/// translation unit of a test executable (it defines the replaceable global operators).
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace flexref::testing {
inline std::atomic<long> g_allocations{0};
inline std::atomic<bool> g_counting{false};

/// Counts the allocations made by f().
template <typename F>
long count_allocations(F&& f) {
  g_allocations = 0;
  g_counting = true;
  f();
  g_counting = false;
  return g_allocations.load();
}
}  // namespace flexref::testing

namespace {

void* counted_allocation(std::size_t size, std::size_t alignment) noexcept {
  if (flexref::testing::g_counting.load()) ++flexref::testing::g_allocations;
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
