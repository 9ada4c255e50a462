#!/usr/bin/env bash
# End-to-end checks of the `flexref` command line: bad input gives a clear error naming the
# file, line and key, a non-zero exit, and no output file; good input writes the CSV and its
# metadata; compare reads them back. Usage: cli_test.sh /path/to/flexref (from the repo root).
set -uo pipefail
flexref=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# 1. A scene with a bad mass: exit 1, message names file, line and key, no output written.
sed 's/^mass = 1.0/mass = -1.0/' scenes/book_toss.toml >"$tmp/bad.toml"
out=$("$flexref" run "$tmp/bad.toml" --scheme c2 --dt 1e-2 -o "$tmp/bad.csv" 2>&1)
code=$?
[[ $code -eq 1 ]] || fail "bad mass: exit code $code, expected 1"
[[ $out == *"bad.toml:"*"mass"* ]] || fail "bad mass: message does not name file and key: $out"
[[ ! -e $tmp/bad.csv ]] || fail "bad mass: an output file was written"

# 2. A step that does not divide the output step / load switch: exit 1, no file.
out=$("$flexref" run scenes/book_toss.toml --scheme c2 --dt 0.003 -o "$tmp/x.csv" 2>&1)
code=$?
[[ $code -ne 0 ]] || fail "non-dividing step accepted"
[[ ! -e $tmp/x.csv ]] || fail "non-dividing step: an output file was written"

# 3. Missing scene file.
"$flexref" check "$tmp/none.toml" >/dev/null 2>&1 && fail "missing scene accepted"

# 4. Good runs: scheme and reference, same columns, compare works.
"$flexref" run scenes/book_toss.toml --scheme c2 --dt 1e-3 -o "$tmp/run.csv" >/dev/null ||
  fail "run failed"
"$flexref" reference scenes/book_toss.toml --solver cvode --rtol 1e-9 --no-estimate \
  -o "$tmp/ref.csv" >/dev/null || fail "reference failed"
[[ -s $tmp/run.csv.meta.toml ]] || fail "no metadata next to run.csv"
[[ $(head -1 "$tmp/run.csv") == $(head -1 "$tmp/ref.csv") ]] || fail "headers differ"
out=$("$flexref" compare "$tmp/run.csv" "$tmp/ref.csv" 2>&1) || fail "compare failed: $out"
[[ $out == *"book.rotation"* ]] || fail "compare output lacks book.rotation: $out"

# 5. compare on a corrupt CSV: exit 1 naming file and line.
cp "$tmp/run.csv" "$tmp/corrupt.csv"
sed -i '5s/^\([^,]*\),[^,]*/\1,abc/' "$tmp/corrupt.csv"
out=$("$flexref" compare "$tmp/corrupt.csv" "$tmp/ref.csv" 2>&1)
code=$?
[[ $code -eq 1 ]] || fail "corrupt CSV: exit code $code"
[[ $out == *"corrupt.csv:5"* ]] || fail "corrupt CSV: message lacks file:line: $out"

# 6. Unknown option value: CLI11 usage error (exit 2... or 105/106 by CLI11 convention).
"$flexref" run scenes/book_toss.toml --scheme rk4 --dt 1e-3 -o "$tmp/y.csv" >/dev/null 2>&1 &&
  fail "unknown scheme accepted"
[[ ! -e $tmp/y.csv ]] || fail "unknown scheme: an output file was written"

if ((failures)); then
  echo "$failures CLI checks failed"
  exit 1
fi
echo "all CLI checks passed"
