#!/usr/bin/env bash
# Builds the library, the command line and the tests with AddressSanitizer + UBSan in a second
# build directory (build-sanitize/) and runs the unit label there, the command-line fuzz target
# and the scene fuzz included. -Og: ASan checks at any level; -Og compiles a quarter faster
# than -O1 (the largest test unit: 60.9 s of CPU against 82.4 s) while the tests run only ~15 %
# slower (29.4 -> 33.8 s on that program's cases; -O0's Eigen made them 3.9x slower), and it
# keeps Eigen's small vectors in memory, where ASan checks every access (docs/performance.md,
# "Build"). -g1 (line tables) keeps the stack traces and compiles faster than -g
# (docs/decisions.md, "Tests").
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
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-Og -g1" -DFLEXREF_SANITIZE=ON -DFLEXREF_BUILD_BENCH=OFF -DFLEXREF_BUILD_STUDY_TESTS=OFF \
  -DFLEXREF_BUILD_PYTHON=OFF -DFLEXREF_BUILD_EXAMPLES=OFF -DFLEXREF_MPI=OFF \
  "${launcher[@]}" "$@" >/dev/null
cmake --build build-sanitize -j"$(nproc)"
cd build-sanitize
# Any report fails the test that triggered it (UBSan does not recover: -fno-sanitize-recover).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
ctest --output-on-failure -j"$(nproc)" -L unit
