#!/usr/bin/env bash
# Integrators outside flexref (docs/external.md), end to end through the command line:
#   converge --external on examples/external/lie_euler.py: order 1 ± 0.1 (Lie-Euler) and
#   2 ± 0.1 (--order 2, the group midpoint rule); converge --runs on the files the first study
#   kept gives the same errors and orders; a failing program is reported with its exit status
#   and output, the study goes on; compare --json; compare refuses what could fool it.
# Usage: external_test.sh /path/to/flexref (from the repository root).
set -uo pipefail
flexref=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { passed=$((passed + 1)); }
program="/usr/bin/python3 examples/external/lie_euler.py {scene} {dt} {output}"
# free_spin on [0, 10]: h|W| <= 0.04, the asymptotic range of both programs.
sed 's/^end_time = 100.0 /end_time = 10.0 /' scenes/free_spin.toml >"$tmp/fs10.toml"

# fitted order of a label in convergence.txt
order_of() { awk -v l="$2" '$1 == l && $2 == "claimed" {print $5}' "$1/convergence.txt" | tr -d ,; }
within() { awk -v x="$1" -v c="$2" 'BEGIN { exit !(x != "" && x >= c - 0.1 && x <= c + 0.1) }'; }

out=$("$flexref" converge "$tmp/fs10.toml" --external "$program" --label euler --order 1 \
  --dt 0.02 --levels 4 --jobs 2 --out "$tmp/c1" 2>&1) || fail "converge --external (order 1): $out"
p=$(order_of "$tmp/c1" euler)
within "$p" 1 && ok || fail "order-1 program: observed '$p', expected 1 +- 0.1: $out"
[[ $out == *"ignored columns: step_count"* ]] && ok || fail "the program's own column is not listed as ignored: $out"
[[ $(ls "$tmp"/c1/run_euler_*.csv | wc -l) -eq 4 ]] && ok || fail "the level files are not kept"

out=$("$flexref" converge "$tmp/fs10.toml" --external "$program --order 2" --label midpoint \
  --dt 0.02 --levels 4 --jobs 2 --out "$tmp/c2" 2>&1) || fail "converge --external (order 2): $out"
p=$(order_of "$tmp/c2" midpoint)
within "$p" 2 && ok || fail "order-2 program: observed '$p', expected 2 +- 0.1: $out"

runs=()
for k in 0 1 2 3; do runs+=("$(awk -v k=$k 'BEGIN { printf "%.17g", 0.02 / 2^k }')=$tmp/c1/run_euler_$k.csv"); done
out=$("$flexref" converge "$tmp/fs10.toml" --runs "${runs[@]}" --label euler --order 1 \
  --out "$tmp/r1" 2>&1) || fail "converge --runs: $out"
# scheme,h,steps,error,order are identical (cpu_seconds is unknown for runs made earlier)
if diff <(cut -d, -f1-5,7 "$tmp/c1/convergence.csv") <(cut -d, -f1-5,7 "$tmp/r1/convergence.csv"); then
  ok
else
  fail "--runs and --external differ on the same files"
fi

# A program that fails: the level is 'failed' with its exit status and output (the study then
# has no valid level and refuses an order: exit 4).
out=$("$flexref" converge "$tmp/fs10.toml" \
  --external "/usr/bin/python3 -c 'import sys; sys.exit(\"diverged at \" + sys.argv[1])' {dt} {output}" \
  --dt 0.02 --levels 3 --out "$tmp/bad" 2>&1)
[[ $out == *"exited with status 1"*"diverged at 0.02"* ]] && ok ||
  fail "a failing program is not reported with status and output: $out"
out=$("$flexref" converge "$tmp/fs10.toml" --external "sleep 10; : {dt} {output}" --timeout 0.3 \
  --dt 0.02 --levels 3 --out "$tmp/slow" 2>&1)
[[ $out == *"timed out after 0.3 s"* ]] && ok || fail "timeout not reported: $out"
out=$("$flexref" converge "$tmp/fs10.toml" --external "true {scene}" --out "$tmp/x" 2>&1)
[[ $? -ne 0 && $out == *"must contain {dt} and {output}"* ]] && ok || fail "bad template accepted: $out"

# work-precision --external: the program's own CPU time, beside the built-in schemes.
out=$("$flexref" work-precision "$tmp/fs10.toml" --external "$program" --label euler \
  --schemes c2 --solvers cvode --tolerances 1e-6 --dt 0.02 --levels 2 --repeats 1 --jobs 1 \
  --out "$tmp/wp" 2>&1) || fail "work-precision --external: $out"
grep -q '^euler,external,0.02,' "$tmp/wp/work_precision.csv" && ok ||
  fail "work-precision CSV lacks the external runs: $(cat "$tmp/wp/work_precision.csv")"
cpu=$(awk -F, '$1 == "euler" && $2 == "external" {print $5; exit}' "$tmp/wp/work_precision.csv")
awk -v c="$cpu" 'BEGIN { exit !(c > 0 && c < 60) }' && ok || fail "external CPU time '$cpu'"

# A program that reports the CPU time of its integration alone (`# cpu_seconds = X`, start-up
# and output excluded, as flexref times its own schemes): work-precision uses it instead of the
# process's whole CPU time; a report above what the process used is refused.
cat >"$tmp/reports_cpu.py" <<'PY'
import shutil, sys, time
t = time.process_time()
while time.process_time() - t < 0.2:  # 0.2 s of start-up work the report leaves out
    pass
shutil.copy(sys.argv[1], sys.argv[3])
with open(sys.argv[3], "a") as f:
    f.write("# cpu_seconds = %s\n" % sys.argv[2])
PY
out=$("$flexref" work-precision "$tmp/fs10.toml" \
  --external "/usr/bin/python3 $tmp/reports_cpu.py $tmp/c1/run_euler_0.csv 1.5e-06 {output} {dt}" \
  --label reported --schemes c2 --solvers cvode --tolerances 1e-6 --dt 0.02 --levels 1 \
  --repeats 1 --jobs 1 --out "$tmp/wp_reported" 2>&1) || fail "work-precision, reported CPU: $out"
cpu=$(awk -F, '$1 == "reported" {print $5; exit}' "$tmp/wp_reported/work_precision.csv")
[[ $cpu == 1.5e-06 || $cpu == 1.5000000000000000e-06 || $cpu == 1.5000000000000002e-06 ]] && ok ||
  fail "the program's reported CPU time is not used: '$cpu': $out"
[[ $out == *"reported: CPU time as reported by the program"* ]] && ok ||
  fail "work-precision does not say whose CPU time it shows: $out"
out=$("$flexref" work-precision "$tmp/fs10.toml" \
  --external "/usr/bin/python3 $tmp/reports_cpu.py $tmp/c1/run_euler_0.csv 100 {output} {dt}" \
  --label overclaim --schemes c2 --solvers cvode --tolerances 1e-6 --dt 0.02 --levels 1 \
  --repeats 1 --jobs 1 --out "$tmp/wp_overclaim" 2>&1)
status=$(awk -F, '$1 == "overclaim" {print $6; exit}' "$tmp/wp_overclaim/work_precision.csv")
[[ $status == *"reports 100 s of CPU"* ]] && ok || fail "an impossible CPU report is accepted: '$status'"

# An engine's own clock, accumulated as t += h over millions of steps, drifts from the output
# times by more than 1e-6 output steps (free_spin on [0, 50] written every 0.001 s, h = 1e-5:
# 5e6 additions, drift up to ~5e-9 > 1e-9); with the run's step known (--runs, --external) the
# contract accepts the drift a clock of that step can have, eps t^2 / h.
sed -e 's/^end_time = 100.0 /end_time = 50.0 /' -e 's/^output_step = 0.1 /output_step = 0.001 /' \
  scenes/free_spin.toml >"$tmp/fs50.toml"
"$flexref" reference "$tmp/fs50.toml" --solver exact --no-estimate -o "$tmp/fs50_exact.csv" \
  >/dev/null || fail "reference of fs50"
/usr/bin/python3 - "$tmp/fs50_exact.csv" "$tmp/drifted.csv" <<'PY'
import sys
rows = [l for l in open(sys.argv[1]) if not l.startswith("#")]
header, data = rows[0], rows[1:]
h, t, n = 1e-5, 0.0, 0
out = [header]
for k in range(0, len(data), 1000):  # every second: the exact states at the engine's clock
    while n < 100 * k:
        t += h
        n += 1
    cells = data[k].split(",")
    cells[0] = repr(t)
    out.append(",".join(cells))
open(sys.argv[2], "w").write("".join(out))
PY
# (the same file for three steps: converge --runs needs three; the coarsest, 1e-5, is checked)
out=$("$flexref" converge "$tmp/fs50.toml" --runs 1e-05="$tmp/drifted.csv" \
  5e-06="$tmp/drifted.csv" 2.5e-06="$tmp/drifted.csv" --label drifted --reference-solver exact \
  --out "$tmp/drift" 2>&1)
status=$(awk -F, '$1 == "drifted" && $2 == 1.0000000000000001e-05 {print $7; exit}' \
  "$tmp/drift/convergence.csv")
[[ $status == ok || $status == round-off ]] && ok || fail "an accumulated clock is refused: '$status' $out"

# compare: the contract's file, JSON, the reference's estimate beside the error.
"$flexref" reference "$tmp/fs10.toml" --solver cvode --rtol 1e-10 -o "$tmp/ref.csv" >/dev/null ||
  fail "reference"
out=$("$flexref" compare --json "$tmp/c1/run_euler_0.csv" "$tmp/ref.csv" 2>&1) || fail "compare --json: $out"
echo "$out" | /usr/bin/python3 -c '
import json, math, sys
d = json.load(sys.stdin)
assert d["metric"]["quantities"] == ["body.rotation"], d
assert d["ignored_columns"] == ["step_count"], d
assert d["certified"] is True and d["reference_estimate"]["value"] > 0, d
# The default metric over the one quantity of the run: 1.669e-2 rad over pi rad, unit 1.
rotation = d["quantities"][0]
assert rotation["name"] == "body.rotation" and abs(rotation["linf"] - 1.669e-2) < 1e-4, d
assert d["metric"]["unit"] == "1" and d["metric"]["terms"] == "largest of body.rotation / pi rad"
assert abs(d["metric"]["value"] - rotation["linf"] / math.pi) <= 1e-15, d["metric"]
' && ok || fail "compare --json: $out"
out=$("$flexref" compare "$tmp/c1/run_euler_0.csv" "$tmp/ref.csv" 2>&1)
[[ $out == *"reference estimated error"*"certified"* ]] && ok || fail "compare text lacks the estimate: $out"
# A reference whose estimate is not 100x below the error: marked NOT CERTIFIED.
"$flexref" reference "$tmp/fs10.toml" --solver cvode --rtol 1e-3 -o "$tmp/loose.csv" >/dev/null
out=$("$flexref" compare "$tmp/c2/run_midpoint_3.csv" "$tmp/loose.csv" 2>&1)
[[ $out == *"NOT CERTIFIED"* ]] && ok || fail "an unmeasurable error is not marked: $out"
# A reference whose estimate found no usable check (estimate = inf): nothing is certified.
cp "$tmp/ref.csv" "$tmp/unknown.csv"
sed 's/^estimate = .*/estimate = inf/' "$tmp/ref.csv.meta.toml" >"$tmp/unknown.csv.meta.toml"
out=$("$flexref" compare --json "$tmp/c1/run_euler_0.csv" "$tmp/unknown.csv" 2>&1)
[[ $? -eq 0 && $out == *'"certified": false'* && $out == *"own error is unknown"* ]] && ok ||
  fail "an unknown (inf) reference estimate: $out"
# All-zero Euler parameters score no error of 0: refused with file, row and column.
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next } NR > 2 { $6 = 0; $7 = 0; $8 = 0; $9 = 0 } { print }' \
  "$tmp/c1/run_euler_0.csv" >"$tmp/zero.csv"
out=$("$flexref" compare "$tmp/zero.csv" "$tmp/ref.csv" 2>&1)
[[ $? -eq 1 && $out == *"zero.csv:3: key 'body.e0': row 1: Euler parameters have norm 0"* ]] && ok ||
  fail "all-zero Euler parameters: $out"

echo "external: $passed passed, $failures failed"
((failures == 0))
