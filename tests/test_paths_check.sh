#!/usr/bin/env bash
# Tests write only inside a folder of their own, unique per process and removed afterwards:
# C++ tests through tests/support/temp_dir.hpp (TempDir, made by mkdtemp), shell tests through
# `mktemp -d` with a trap that removes it. A fixed name in the shared temporary folder collides
# when two builds' suites run at once (Release and sanitizers in CI) and a file left behind
# changes the next run's verdict. This check fails on a C++ test source that names the
# temporary folder or makes temporary names itself (comments aside), and on a shell test whose `mktemp -d` has
# no removing trap.
# Usage: test_paths_check.sh TESTS_DIR
set -euo pipefail
tests=$1
status=0
while IFS= read -r hit; do
  echo "FAIL: $hit (write into a testing::TempDir, tests/support/temp_dir.hpp)"
  status=1
done < <(grep -rnE --include='*.cpp' --include='*.hpp' \
  'temp_directory_path|"/tmp|P_tmpdir|tmpnam|mkstemp|mkdtemp|to_string\((::)?getpid' "$tests" |
  grep -vE "^$tests/support/temp_dir\.(cpp|hpp):" | grep -vE '^[^:]+:[0-9]+:\s*//' || true)
while IFS= read -r script; do
  if grep -q 'mktemp' "$script" && ! grep -qE "^trap 'rm -rf \"\\\$[a-z_]+\"' EXIT" "$script"; then
    echo "FAIL: $script makes a temporary folder without a trap that removes it"
    status=1
  fi
  if grep -nE '/tmp/' "$script" | grep -vE '^\s*[0-9]+:\s*#' | grep -qv 'ls /tmp'; then
    echo "FAIL: $script names a path in /tmp: $(grep -nE '/tmp/' "$script" | head -1)"
    status=1
  fi
done < <(find "$tests" -name '*.sh' ! -name "$(basename "$0")")
exit $status
