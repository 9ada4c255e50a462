#!/usr/bin/env bash
# Builds the library, the command line and the tests with AddressSanitizer + UBSan in a second
# build directory (build-sanitize/) and runs the unit label there, the command-line fuzz target
# and the scene fuzz included: the test command (scripts/test.sh) runs the unit tests here only.
# The long measurements (label study) are compiled, not run, so that they build. -O1: ASan's
# recommended optimization, a shorter build than -O2 and tests several times faster than -O0; -g1 (line tables) keeps the stack
# traces and compiles faster than -g (docs/decisions.md, "Tests").
# Left out of this build: the Python module (the interpreter would need the ASan runtime
# preloaded), the installed-package examples (a second project), and MPI (OpenMPI's own
# allocations are reported as leaks); the studies' one-process distribution path runs here.
# Usage: scripts/test_sanitized.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
generator=()
[[ -f build-sanitize/CMakeCache.txt ]] || ! command -v ninja >/dev/null || generator=(-G Ninja)  # as setup.sh
cmake -S . -B build-sanitize "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DFLEXREF_SANITIZE=ON -DFLEXREF_BUILD_BENCH=OFF -DFLEXREF_BUILD_STUDY_TESTS=ON \
  -DFLEXREF_BUILD_PYTHON=OFF -DFLEXREF_BUILD_EXAMPLES=OFF -DFLEXREF_MPI=OFF \
  "${launcher[@]}" "$@" >/dev/null
cmake --build build-sanitize -j"$(nproc)"
cd build-sanitize
# Any report fails the test that triggered it (UBSan does not recover: -fno-sanitize-recover).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
ctest --output-on-failure -j"$(nproc)" -L unit
