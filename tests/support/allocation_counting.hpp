#pragma once
/// \file allocation_counting.hpp
/// Replaces the global operator new/delete of a test program with versions that count
/// allocations while `flexref::testing::g_counting` is set, and (with glibc, outside
/// AddressSanitizer builds, which intercept malloc themselves) interposes malloc, calloc and
/// realloc too: Eigen allocates its heap matrices with std::malloc, not operator new, so
/// counting operator new alone would not see them. Include in exactly ONE translation unit of
/// a test executable (it defines the replaceable global operators and the C allocators).
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

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
// glibc exports its allocator under these names; a program that defines malloc interposes it
// for every shared library it loads, Eigen's inline code included.
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);

void* malloc(std::size_t size) noexcept {
  if (flexref::testing::g_counting.load(std::memory_order_relaxed))
    ++flexref::testing::g_allocations;
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  if (flexref::testing::g_counting.load(std::memory_order_relaxed))
    ++flexref::testing::g_allocations;
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  if (flexref::testing::g_counting.load(std::memory_order_relaxed))
    ++flexref::testing::g_allocations;
  return __libc_realloc(pointer, size);
}
}
#endif

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
