#!/usr/bin/env bash
# The test command (README): installs what is missing, then builds flexref twice, side by side on
# the machine's cores, and runs every test but the long `study` and `long` labels:
#   - Release, in build/ (the main job's folder): the library, the command line, the benchmarks,
#     the Python module and the examples; it runs the tests of what only it builds (the Python
#     module, the installed package, the engines' examples, MPI) and the README's commands.
#   - AddressSanitizer + UBSan, in build-sanitize/ (scripts/test_sanitized.sh): the unit test
#     programs and the command line's scripts (label `unit`).
# The unit tests are compiled and run in the sanitized build only, not a second time in Release:
# at -O1 with the sanitizers they check more (every out-of-bounds access, dangling reference and
# undefined operation on the paths they run, and Eigen's assertions, which -DNDEBUG removes in
# Release), and the double arithmetic is the same as -O3's on x86-64 (no -ffast-math; no FMA
# contraction without -march). Compiling them twice was a quarter of CI's CPU (docs/performance.md,
# "Build"; docs/decisions.md, "Tests"). A folder configured with the defaults
# (FLEXREF_BUILD_UNIT_TESTS=ON) still builds them in Release; `ctest -L unit` runs them there.
# Usage: scripts/test.sh   (exit 0 when both pass)
set -uo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --packages-only || exit
sanitized_log=$(mktemp)
trap 'rm -f "$sanitized_log"' EXIT
bash scripts/test_sanitized.sh >"$sanitized_log" 2>&1 &
sanitized=$!
(
  set -e
  bash scripts/setup.sh -DFLEXREF_BUILD_UNIT_TESTS=OFF -DFLEXREF_BUILD_STUDY_TESTS=OFF
  cd build
  ctest --output-on-failure -j"$(nproc)" -LE 'study|long'
)
release_status=$?
wait "$sanitized"
sanitized_status=$?
echo "=== scripts/test_sanitized.sh (exit $sanitized_status) ==="
cat "$sanitized_log"
echo "=== Release build and tests exit $release_status, scripts/test_sanitized.sh exit $sanitized_status ==="
((release_status == 0 && sanitized_status == 0))
