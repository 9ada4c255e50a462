#!/usr/bin/env bash
# The checks of the tests themselves (approx_check.sh, test_paths_check.sh) fail on each form
# they exist to catch and pass on its repaired form: each case is a one-file tests folder made
# here, with the line under test in a small test case.
# Usage: check_scripts_test.sh TESTS_DIR (where the two checks are)
set -uo pipefail
checks=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
fail() {
  echo "FAIL: $*"
  status=1
}

# case_of CHECK EXPECTED NAME FILE TEXT: FILE (under its own folder, case<n>/) with TEXT joins
# the tests folder of CHECK's cases that must fail (EXPECTED = fails: the check must report
# that file) or pass (EXPECTED = passes: the check must report nothing). Each check then runs
# once on each folder.
n=0
declare -A names
case_of() {
  local check=$1 expected=$2 name=$3 file=$4 text=$5
  n=$((n + 1))
  local dir="$tmp/$check.$expected/case$n"
  mkdir -p "$dir/$(dirname "$file")"
  printf '%s\n' "$text" >"$dir/$file"
  names["$check.$expected/case$n/$file"]=$name
}

verify() {
  local check=$1 out code key
  out=$(bash "$checks/$check" "$tmp/$check.fails" 2>&1)
  code=$?
  [[ $code -eq 1 ]] || fail "$check passes a folder of refused forms (exit $code): $out"
  for key in "${!names[@]}"; do
    [[ $key == "$check.fails/"* ]] || continue
    [[ $out == *"FAIL: $tmp/$key:"* || $out == *"FAIL: $tmp/$key "* ]] ||
      fail "$check does not catch ${names[$key]}"
  done
  out=$(bash "$checks/$check" "$tmp/$check.passes" 2>&1)
  code=$?
  [[ $code -eq 0 && -z $out ]] || fail "$check refuses a repaired form (exit $code): $out"
}

cpp() {  # a test case around the lines given
  printf 'TEST_CASE("x") {\n%s\n}\n' "$1"
}

# approx_check.sh
a=approx_check.sh
case_of $a fails "a bare Approx" x/a_test.cpp "$(cpp '  // derived
  CHECK(x == Approx(1.0));')"
case_of $a fails "a bare Catch::Approx" x/a_test.cpp "$(cpp '  // derived
  CHECK(x == Catch::Approx(1.0));')"
case_of $a fails "isApprox without its precision" x/a_test.cpp "$(cpp '  // derived
  CHECK(a.isApprox(b));')"
case_of $a fails "an epsilon no comment derives" x/a_test.cpp "$(cpp '  CHECK(x == Approx(1.0).epsilon(1e-12));')"
case_of $a fails "std::abs(a - b) < tol without a derivation" x/a_test.cpp "$(cpp '  const double e = 1.0;

  CHECK(std::abs(a - b) < 1e-12);')"
case_of $a fails "a norm below a named bound defined without a derivation" x/a_test.cpp "$(cpp '  const double bound = 1e-9;

  CHECK((a - b).norm() <= bound);')"
case_of $a fails "a residual below a literal bound" x/a_test.cpp "$(cpp '  CHECK(r.force <= 1e-5);')"
case_of $a passes "a derived epsilon" x/a_test.cpp "$(cpp '  // Two roundings: 2 ε.
  CHECK(x == Approx(1.0).epsilon(1e-15));')"
case_of $a passes "a bound derived at its definition" x/a_test.cpp "$(cpp '  // Round-off of 10 terms: 1e-14.
  const double bound = 1e-14;

  CHECK(std::abs(a - b) <= bound);')"
case_of $a passes "a literal the definition's comment derives" x/a_test.cpp "$(cpp '  // Truncation h² ~ 1e-10: the tolerance 1e-7.

  CHECK(std::abs(a - b) <= 1e-7);')"
case_of $a passes "an exact comparison" x/a_test.cpp "$(cpp '  CHECK(x == 1e-9);
  CHECK(std::vector<double>{1e5} == v);')"

# test_paths_check.sh
p=test_paths_check.sh
case_of $p fails "temp_directory_path" x/p_test.cpp "$(cpp '  auto d = std::filesystem::temp_directory_path();')"
case_of $p fails "TMPDIR in C++" x/p_test.cpp "$(cpp '  const char* d = std::getenv("TMPDIR");')"
case_of $p fails "a literal /dev path" x/p_test.cpp "$(cpp '  write(f, "/dev/full");')"
case_of $p fails "a literal /var path" x/p_test.cpp "$(cpp '  const std::string out = "/var/tmp/x.csv";')"
case_of $p fails "an ofstream at a literal path" x/p_test.cpp "$(cpp '  std::ofstream("out.csv") << 1;')"
case_of $p fails "write_csv at a literal path" x/p_test.cpp "$(cpp '  write_csv(table, "run.csv");')"
case_of $p passes "paths under the TempDir, own descriptors, a missing file" x/p_test.cpp \
  "$(cpp '  std::ofstream(tmp.path() / "a.csv") << 1;
  write_output_file("/dev/fd/" + std::to_string(fd), "text\n");
  read_scene("/nonexistent/scene.toml");')"
case_of $p fails "mktemp without its trap" x/t.sh 'd=$(mktemp -d)'
case_of $p fails "a write into /tmp" x/t.sh 'echo 1 >/tmp/x.txt'
case_of $p fails "\$TMPDIR named" x/t.sh 'cp a.csv "$TMPDIR/a.csv"'
case_of $p fails "a listing of /tmp that ignores \$TMPDIR" x/t.sh 'ls /tmp | grep -q flexref-'
case_of $p fails "a /dev path" x/t.sh '"$flexref" run s.toml -o "$o" 2>/dev/full'
case_of $p fails "a redirection to a relative path" x/t.sh 'echo 1 > out.csv'
case_of $p fails "-o to a literal path" x/t.sh '"$flexref" run s.toml -o run.csv'
case_of $p fails "--out to an absolute path" x/t.sh '"$flexref" converge s.toml --out /srv/study'
case_of $p passes "outputs under the test's folder" x/t.sh 'tmp=$(mktemp -d)
trap '"'"'rm -rf "$tmp"'"'"' EXIT
"$flexref" run s.toml -o "$tmp/run.csv" >/dev/null 2>"$tmp/err.txt"
grep -o "use --dt [0-9.]*" "$tmp/err.txt" >"$tmp/dt.txt"
find "$tmp" \( -name "*.csv" -o -name "*.txt" \) | sort >"$tmp/list.txt"
ls "${TMPDIR:-/tmp}" | grep -q "^flexref-" && echo left'

verify approx_check.sh
verify test_paths_check.sh
[[ $status -eq 0 ]] && echo "ok: $n cases"
exit $status
