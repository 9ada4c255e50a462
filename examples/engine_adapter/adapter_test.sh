#!/usr/bin/env bash
# An engine adapter (docs/engines.md) against flexref's exact solution of a torque-free body,
# end to end:
#   - free_spin on [0, 2] (J = diag(3, 4, 5), |W| <= 2.05 rad/s) at h = 0.02 and 0.01 for every
#     integrator given: the attitude and the angular velocity within the integrator's error
#     bound, and their orders from the two steps within 0.3 of the orders given;
#   - converge --external with the adapter, unchanged: an observed order from three levels;
#   - the file: the trajectory contract's columns and the engine's `# cpu_seconds` report;
#   - refusals: a scene part the engine cannot map (exit 1, naming the scene key), a step off
#     the output grid (exit 1), an unknown integrator (exit 2), an output that cannot be written
#     (exit 5), and no file left behind by a failed run.
# Usage: adapter_test.sh FLEXREF ADAPTER "INTEGRATOR:P_ATTITUDE:P_ANGULAR_VELOCITY ..."
#        UNMAPPABLE_SCENE KEY   (from the repository root)
set -uo pipefail
flexref=$1
adapter=$2
integrators=$3
unmappable=$4
unmappable_key=$5
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { passed=$((passed + 1)); }

sed 's/^end_time = 100.0 /end_time = 2.0 /' scenes/free_spin.toml >"$tmp/fs2.toml"
"$flexref" reference "$tmp/fs2.toml" --solver exact -o "$tmp/exact.csv" >/dev/null ||
  fail "exact reference"

# The L-infinity errors of a run's attitude and angular velocity against the exact solution.
errors_of() {
  "$flexref" compare --json "$1" "$tmp/exact.csv" | /usr/bin/python3 -c '
import json, sys
q = {x["name"]: x["linf"] for x in json.load(sys.stdin)["quantities"]}
print(q["body.rotation"], q["body.angular_velocity"])'
}

# The error bound of an order-p one-step method after time T on a motion of rate w: its local
# error is C (h w)^(p+1) per step with an error constant C below 1 for every method here
# (Euler 1/2, the Runge-Kutta methods' 1/(p+1)! and below), T/h steps add up to
# T w (h w)^p. T = 2 s, w = 2.05 rad/s (|W| of free_spin, whose energy and momentum bound it).
bound() { awk -v h="$1" -v p="$2" 'BEGIN { w = 2.05; printf "%.3e", 2 * w * (h * w)^p }'; }
# log2(e1 / e2) within 0.3 of p
order_ok() { awk -v a="$1" -v b="$2" -v p="$3" 'BEGIN { o = log(a / b) / log(2); exit !(o > p - 0.3 && o < p + 0.3) }'; }
below() { awk -v e="$1" -v b="$2" 'BEGIN { exit !(e > 0 && e <= b) }'; }

for spec in $integrators; do
  IFS=: read -r integrator p_rot p_w <<<"$spec"
  for h in 0.02 0.01; do
    "$adapter" "$tmp/fs2.toml" $h "$tmp/${integrator}_$h.csv" --integrator "$integrator" \
      >/dev/null 2>"$tmp/err" || fail "$integrator at h = $h: $(cat "$tmp/err")"
  done
  read -r rot1 w1 <<<"$(errors_of "$tmp/${integrator}_0.02.csv")"
  read -r rot2 w2 <<<"$(errors_of "$tmp/${integrator}_0.01.csv")"
  for q in "rotation $p_rot $rot1 $rot2" "angular_velocity $p_w $w1 $w2"; do
    read -r metric p e1 e2 <<<"$q"
    b=$(bound 0.02 "$p")
    below "$e1" "$b" && ok || fail "$integrator $metric: error $e1 at h = 0.02 above its bound $b"
    order_ok "$e1" "$e2" "$p" && ok ||
      fail "$integrator $metric: errors $e1, $e2 at h = 0.02, 0.01 are not of order $p"
  done
done

# The contract's columns, the engine's CPU report.
first=${integrators%% *}
first=${first%%:*}
header=$(grep -v '^#' "$tmp/${first}_0.01.csv" | head -1)
[[ $header == "t,body.x,body.y,body.z,body.e0,body.e1,body.e2,body.e3,body.vx,body.vy,body.vz,body.W1,body.W2,body.W3,body.corner.x,body.corner.y,body.corner.z" ]] &&
  ok || fail "columns: $header"
grep -Eq '^# cpu_seconds = [0-9.e+-]+$' "$tmp/${first}_0.01.csv" && ok ||
  fail "no '# cpu_seconds' report: $(tail -2 "$tmp/${first}_0.01.csv")"

# converge --external, unchanged: three levels, an order.
p_first=$(echo "$integrators" | awk '{ split($1, a, ":"); print a[2] }')
out=$("$flexref" converge "$tmp/fs2.toml" --external "$adapter {scene} {dt} {output} --integrator $first" \
  --label engine --dt 0.02 --levels 3 --metric rotation --reference-solver exact --jobs 1 \
  --out "$tmp/converge" 2>&1) || fail "converge --external: $out"
observed=$(awk '$1 == "engine" && $2 == "claimed" {print $5}' "$tmp/converge/convergence.txt")
awk -v o="$observed" -v p="$p_first" 'BEGIN { exit !(o != "" && o > p - 0.3 && o < p + 0.3) }' &&
  ok || fail "converge --external: observed '$observed', expected $p_first: $out"

# Refusals.
out=$("$adapter" "$unmappable" 0.01 "$tmp/no.csv" 2>&1)
code=$?
[[ $code -eq 1 && $out == *"key '$unmappable_key'"* ]] && ok ||
  fail "an unmappable scene: exit $code, $out"
out=$("$adapter" "$tmp/fs2.toml" 0.03 "$tmp/no.csv" 2>&1)
code=$?
[[ $code -eq 1 && $out == *"not on the step grid"* ]] && ok || fail "a step off the grid: exit $code, $out"
out=$("$adapter" "$tmp/fs2.toml" 0.01 "$tmp/no.csv" --integrator none 2>&1)
code=$?
[[ $code -eq 2 ]] && ok || fail "an unknown integrator: exit $code, $out"
out=$("$adapter" "$tmp/fs2.toml" 0.01 "$tmp/missing/no.csv" 2>&1)
code=$?
[[ $code -eq 5 ]] && ok || fail "an unwritable output: exit $code, $out"
[[ -z $(find "$tmp" -maxdepth 2 -name '*no.csv*') ]] && ok || fail "a failed run left a file"

echo "$(basename "$adapter"): $passed passed, $failures failed"
((failures == 0))
