#!/usr/bin/env bash
# The test command (README): installs what is missing, then builds flexref once, with
# AddressSanitizer + UBSan in build-sanitize/ (scripts/test_sanitized.sh), and runs every test but
# the long `study` and `long` labels there: the unit tests, the command line's scripts, the
# README's commands, the Python module, the installed package, the engines' examples, MPI and
# CalculiX. One build, not a Release build beside it: the library compiled twice was two fifths
# of CI's CPU, and at -O1 with the sanitizers the tests check more (every out-of-bounds access,
# dangling reference and undefined operation on the paths they run, and Eigen's assertions, which
# -DNDEBUG removes in Release), while the double arithmetic is the same as -O3's on x86-64 (no
# -ffast-math; no FMA contraction without -march). docs/performance.md, "Build";
# docs/decisions.md, "Tests". The main job's Release build is scripts/setup.sh's.
# Usage: scripts/test.sh   (exit 0 when every test passes)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --packages-only
exec bash scripts/test_sanitized.sh
