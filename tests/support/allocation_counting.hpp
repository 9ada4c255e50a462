#pragma once
/// \file allocation_counting.hpp
/// Counting the allocations of a piece of code. Every test program links
/// tests/support/allocation_counting.cpp, which replaces the global operator new/delete with
/// versions that count allocations while `flexref::testing::g_counting` is set, and (with glibc,
/// outside AddressSanitizer builds, which intercept malloc themselves) interposes malloc, calloc
/// and realloc too: Eigen allocates its heap matrices with std::malloc, not operator new, so
/// counting operator new alone would not see them. Outside count_allocations the replacements
/// cost one relaxed atomic load per allocation.
#include <atomic>
#include <cstddef>

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
