#!/usr/bin/env bash
# Builds everything with AddressSanitizer + UBSan in build-sanitize/ and runs the unit label
# there: the unit tests, the command line's scripts and fuzz, the README's commands, the Python
# module (its interpreter preloads ASan's runtime), the installed package, the engines' examples,
# MPI and CalculiX. This is the test command's one build (scripts/test.sh; docs/decisions.md,
# "Tests"). The long measurements (labels study and long) and the benchmarks are compiled, not
# run, so that they build. -O1: ASan's recommended optimization, a shorter build than -O2 and
# tests several times faster than -O0; -g1 (line tables) keeps the stack traces and compiles
# faster than -g.
# Usage: scripts/test_sanitized.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
generator=()
[[ -f build-sanitize/CMakeCache.txt ]] || ! command -v ninja >/dev/null || generator=(-G Ninja)  # as setup.sh
cmake -S . -B build-sanitize "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DFLEXREF_SANITIZE=ON -DFLEXREF_BUILD_STUDY_TESTS=ON \
  "${launcher[@]}" "$@" >/dev/null
cmake --build build-sanitize -j"$(nproc)"
cd build-sanitize
# Any report fails the test that triggered it (UBSan does not recover: -fno-sanitize-recover).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
ctest --output-on-failure -j"$(nproc)" -L unit
