/// \file allocation_counting.cpp
/// The replaceable global allocation functions and glibc's C allocators, counting while
/// flexref::testing::g_counting is set (allocation_counting.hpp). Linked once into every test
/// program (tests/CMakeLists.txt) and into the benchmarks that count.
#include "tests/support/allocation_counting.hpp"

#include <cstddef>
#include <cstdlib>
#include <new>

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
