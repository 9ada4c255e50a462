#!/usr/bin/env bash
# Set up, build, and run the test suite (ctest; the long `study` label is excluded).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd build
ctest --output-on-failure -j"$(nproc)" -LE study
