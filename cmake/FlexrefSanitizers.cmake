# -DFLEXREF_SANITIZE=ON builds everything with AddressSanitizer and UBSan.
# UBSan without its `null` and `alignment` checks: they instrument every pointer access and cost a
# third of this build's compile time (measured on a test batch: 23.5 s with them, 15.6 s
# without, 15.2 s for ASan alone), while a null access still ends the test with ASan's SEGV
# report and its stack, and x86-64 tolerates the misaligned loads the second would flag. The
# checks that found defects here (invalid enum and bool loads, bounds, shifts, overflow) stay.
# ASan without its use-after-scope check (a reference kept to a stack object past the end of its
# scope): it poisons and unpoisons every local's storage at its scope's entry and exit, which in
# Eigen's inlined expressions is most of the instrumentation, a third of a batch's compile
# (constraint's library batch: 43.5 s of CPU with it, 30.5 s without), so that with it the one
# CI build did not fit CI's budget (docs/decisions.md, "Tests"). Heap use-after-free, double
# free, leaks and out-of-bounds access on heap, stack and globals stay checked.
if(FLEXREF_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize=null,alignment
                      -fno-sanitize-address-use-after-scope -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
  # A program not built here that loads this build's code (the Python interpreter importing the
  # module) needs ASan's runtime loaded before anything else, with the C++ runtime beside it (the
  # runtime's interceptor of __cxa_throw finds no libstdc++ in a C program otherwise): its tests
  # preload both (FLEXREF_SANITIZER_PRELOAD, tests/CMakeLists.txt). The interpreter's own
  # allocations live to its exit by design, so leak detection is off there; every other check
  # stays on.
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so
                  OUTPUT_VARIABLE flexref_asan_runtime OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT IS_ABSOLUTE "${flexref_asan_runtime}" OR NOT EXISTS "${flexref_asan_runtime}")
    message(FATAL_ERROR "FLEXREF_SANITIZE: the compiler names no ASan runtime (libasan.so)")
  endif()
  set(FLEXREF_SANITIZER_NO_LEAKS "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1")
  set(FLEXREF_SANITIZER_PRELOAD "LD_PRELOAD=${flexref_asan_runtime}:libstdc++.so.6"
                                ${FLEXREF_SANITIZER_NO_LEAKS})
endif()
