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

# 7. Flexible scenes: check prints the modal frequencies and the explicit step limit.
out=$("$flexref" check scenes/flexible_spinner.toml 2>&1) || fail "check flexible_spinner: $out"
[[ $out == *"bending-xy-1"*"rad/s"*"Hz"* ]] || fail "check lacks mode names/frequencies: $out"
[[ $out == *"2/omega_max"* ]] || fail "check lacks the explicit step limit: $out"
for scene in rotating_cantilever spin_up_beam spin_up_beam_4 spin_up_beam_6; do
  "$flexref" check "scenes/$scene.toml" >/dev/null 2>&1 || fail "check $scene failed"
done

# 8. reference --model lte on flexible scenes: modal and drive-torque columns, model recorded.
for scene in flexible_spinner spin_up_beam; do
  "$flexref" reference "scenes/$scene.toml" --model lte --rtol 1e-8 --no-estimate \
    -o "$tmp/$scene.csv" >/dev/null || fail "reference --model lte $scene failed"
  grep -q '^model = "lte"' "$tmp/$scene.csv.meta.toml" ||
    fail "$scene: meta.toml does not record model = \"lte\""
done
header=$(head -1 "$tmp/flexible_spinner.csv")
[[ $header == *"spinner.tip.x"*"spinner.q4,spinner.qd1"*"spinner.qd4,energy" ]] ||
  fail "flexible_spinner CSV columns: $header"
[[ $(head -1 "$tmp/spin_up_beam.csv") == *"beam.qd4,beam.drive_torque,energy" ]] ||
  fail "spin_up_beam CSV lacks beam.drive_torque"
"$flexref" reference scenes/rotating_cantilever.toml --rtol 1e-8 --no-estimate \
  -o "$tmp/rc.csv" >/dev/null || fail "reference rotating_cantilever (coupled) failed"
grep -q '^model = "coupled"' "$tmp/rc.csv.meta.toml" || fail "default model is not coupled"

# 9. run --model lte on a flexible scene; a step above 2/omega_max warns on stderr.
sed 's/^output_step = 0.01 /output_step = 0.1 /' scenes/flexible_spinner.toml >"$tmp/fs.toml"
"$flexref" run scenes/flexible_spinner.toml --model lte --scheme c2 --dt 0.01 \
  -o "$tmp/fs_run.csv" >/dev/null 2>"$tmp/err.txt" || fail "run --model lte flexible_spinner"
[[ ! -s $tmp/err.txt ]] || fail "run below the step limit warned: $(cat "$tmp/err.txt")"
grep -q '^model = "lte"' "$tmp/fs_run.csv.meta.toml" || fail "run meta.toml lacks the model"
"$flexref" run "$tmp/fs.toml" --model lte --scheme c2 --dt 0.1 -o "$tmp/fs_big.csv" \
  >/dev/null 2>"$tmp/err.txt"
grep -q "warning: step 0.1 s exceeds 2/omega_max" "$tmp/err.txt" ||
  fail "no step-limit warning: $(cat "$tmp/err.txt")"
# A scheme the flexible model does not support is bad input (exit 1, no file), not a crash.
out=$("$flexref" run scenes/spin_up_beam.toml --model coupled --scheme c2 --dt 0.01 \
  -o "$tmp/coupled_run.csv" 2>&1)
code=$?
if ((code != 0)); then
  [[ $code -eq 1 ]] || fail "unsupported scheme/model: exit code $code: $out"
  [[ ! -e $tmp/coupled_run.csv ]] || fail "unsupported scheme/model: an output file was written"
fi
# Flexible bodies have no exact solution: --solver exact is bad input.
out=$("$flexref" reference scenes/flexible_spinner.toml --solver exact -o "$tmp/ex.csv" 2>&1)
code=$?
[[ $code -eq 1 ]] || fail "reference --solver exact on a flexible scene: exit $code: $out"
[[ ! -e $tmp/ex.csv ]] || fail "reference --solver exact on a flexible scene wrote a file"
# Unknown --model value: CLI11 usage error.
"$flexref" run scenes/spin_up_beam.toml --model rigid -o "$tmp/z.csv" >/dev/null 2>&1 &&
  fail "unknown --model accepted"

# Contact and joint scenes: check prints each penalty element's frequency and step limit;
# reference writes the dissipated work and the energy balance, and counts the events.
for scene in bouncing_ball sliding_block top_on_plane tippe_top pendulum_on_sliding_support \
  double_pendulum_impacts; do
  out=$("$flexref" check "scenes/$scene.toml" 2>&1) || fail "check $scene failed: $out"
  [[ $out == *"explicit step limit 2/omega"* ]] || fail "check $scene: no penalty step limit: $out"
  out=$("$flexref" reference "scenes/$scene.toml" --rtol 1e-8 --no-estimate \
    -o "$tmp/$scene.csv" 2>&1) || fail "reference $scene failed: $out"
  [[ $out == *"events located"* ]] || fail "reference $scene: no event count: $out"
  head -1 "$tmp/$scene.csv" | grep -q ',energy,dissipated_work,energy_balance$' ||
    fail "$scene: CSV lacks dissipated_work and energy_balance"
  grep -q '^events = ' "$tmp/$scene.csv.meta.toml" || fail "$scene: meta.toml lacks events"
  grep -q '^event_times = \[' "$tmp/$scene.csv.meta.toml" || fail "$scene: meta.toml lacks event_times"
done
out=$("$flexref" check scenes/pendulum_on_sliding_support.toml 2>&1)
[[ $out == *"joint[1] angular: omega = sqrt(k/I_eff)"* ]] || fail "check: no angular joint mode: $out"
# The event count of the bouncing ball: two per bounce.
grep -q '^events = [1-9][0-9]*$' "$tmp/bouncing_ball.csv.meta.toml" || fail "bouncing_ball: no events"
# run warns when the step exceeds a contact's explicit limit, and still runs.
out=$("$flexref" run scenes/bouncing_ball.toml --scheme c2 --dt 0.01 -o "$tmp/bb_run.csv" 2>&1) ||
  fail "run bouncing_ball failed: $out"
[[ $out == *"warning: step 0.01 s exceeds 2/omega"*"contact[1]"* ]] ||
  fail "run bouncing_ball: no step-limit warning: $out"
out=$("$flexref" run scenes/bouncing_ball.toml --scheme c2 --dt 1e-3 -o "$tmp/bb_run.csv" 2>&1)
[[ $out != *"warning"* ]] || fail "run bouncing_ball below the limit warned: $out"
# compare: run and reference files of a contact scene have the same columns.
"$flexref" compare "$tmp/bb_run.csv" "$tmp/bouncing_ball.csv" >/dev/null 2>&1 ||
  fail "compare of bouncing_ball run and reference failed"
# A bad contact key names file, line and key.
sed 's/^radius = 0.1 /radius = -0.1 /' scenes/bouncing_ball.toml >"$tmp/bad_contact.toml"
out=$("$flexref" check "$tmp/bad_contact.toml" 2>&1)
[[ $? -eq 1 && $out == *"bad_contact.toml:"*"contact[1].radius"* ]] ||
  fail "bad contact radius: $out"

# figure: a paper study file, shortened; table and CSV written, failed runs explained.
sed 's/^end_time = 20.0/end_time = 2.0/' studies/paper/fig1_free_spin.toml >"$tmp/fig1.toml"
sed -i 's|scene = "../../scenes/free_spin.toml"|scene = "'"$PWD"'/scenes/free_spin.toml"|' "$tmp/fig1.toml"
out=$("$flexref" figure "$tmp/fig1.toml" --jobs 2 --out "$tmp/fig1" 2>&1) ||
  fail "figure failed: $out"
[[ -s "$tmp/fig1/figure.csv" && -s "$tmp/fig1/study.toml" && $out == *"completed"* ]] ||
  fail "figure: missing outputs: $out"
printf '[figure]\nscene = "%s/scenes/free_spin.toml"\nsteps = [0.3]\n' "$PWD" >"$tmp/fig_bad.toml"
out=$("$flexref" figure "$tmp/fig_bad.toml" --out "$tmp/fig_bad" 2>&1)
[[ $? -eq 1 && $out == *"fig_bad.toml:"*"figure.steps"* ]] || fail "figure bad step: $out"
# lte-map on a tiny grid; bad ratios and a scene without a flexible body are refused.
"$flexref" lte-map scenes/flexible_spinner.toml --spin-ratios 0.02,0.05 --inertia-ratios 1e-4,0.1 \
  --end-time 1 --jobs 2 --out "$tmp/lte" >/dev/null 2>&1 || fail "lte-map failed"
[[ $(wc -l <"$tmp/lte/lte_map.csv") -eq 5 && -s "$tmp/lte/study.toml" ]] ||
  fail "lte-map: expected 4 grid rows and study.toml"
"$flexref" lte-map scenes/flexible_spinner.toml --inertia-ratios 0.1,-1 --out "$tmp/lte_bad" \
  >/dev/null 2>&1
[[ $? -eq 1 ]] || fail "lte-map accepted a negative inertia ratio"
"$flexref" lte-map scenes/free_spin.toml --out "$tmp/lte_bad" >/dev/null 2>&1
[[ $? -eq 1 ]] || fail "lte-map accepted a scene without a flexible body"
# modes on two small bases; one count or a rigid scene is refused; the 64-mode scene reads.
"$flexref" modes scenes/flexible_spinner.toml --modes 2,4 --end-time 0.5 --jobs 2 \
  --out "$tmp/modes" >/dev/null 2>&1 || fail "modes failed"
[[ $(wc -l <"$tmp/modes/modes.csv") -eq 3 && -s "$tmp/modes/study.toml" ]] ||
  fail "modes: expected 2 rows and study.toml"
"$flexref" modes scenes/flexible_spinner.toml --modes 4 --out "$tmp/modes_bad" >/dev/null 2>&1
[[ $? -eq 1 ]] || fail "modes accepted a single mode count"
"$flexref" modes scenes/free_spin.toml --out "$tmp/modes_bad" >/dev/null 2>&1
[[ $? -eq 1 ]] || fail "modes accepted a scene without a flexible body"
out=$("$flexref" check scenes/flexible_spinner_64.toml 2>&1) || fail "check flexible_spinner_64: $out"
[[ $out == *"bending-xz-32"* ]] || fail "flexible_spinner_64 lacks its 64th mode: $out"
# stability against modal frequency: the limit 2/omega.
out=$("$flexref" stability --parameter modal_frequency --values 50 --schemes c2 \
  --out "$tmp/stab_modal" 2>&1) || fail "stability modal_frequency failed: $out"
[[ $out == *"1.999"* ]] || fail "stability modal_frequency: h*omega not 1.999: $out"
# reference: the method and why (CVODE chooses Adams on a scene without a stiff element; BDF on
# request), ARKODE, and an estimate that says how it was made.
"$flexref" reference scenes/free_spin.toml --solver cvode --rtol 1e-8 -o "$tmp/fs.csv" >/dev/null ||
  fail "reference free_spin failed"
meta=$(cat "$tmp/fs.csv.meta.toml")
[[ $meta == *'method = "adams"'*'method_reason = "non-stiff'* ]] ||
  fail "reference: no automatic method in the metadata: $meta"
[[ $meta == *"[error_estimate]"*'method = "distance to the exact solution'*"[[error_estimate.check]]"*'role = "exact"'* ]] ||
  fail "reference: the estimate does not say how it was made: $meta"
"$flexref" reference scenes/book_toss.toml --solver cvode --method bdf --rtol 1e-8 -o "$tmp/bt.csv" \
  >/dev/null || fail "reference --method bdf failed"
meta=$(cat "$tmp/bt.csv.meta.toml")
[[ $meta == *'method = "bdf"'*'method_reason = "chosen with --method"'* ]] ||
  fail "reference --method bdf not recorded: $meta"
[[ $meta == *'role = "tighter"'*'used = true'*'role = "other"'*'solver = "odeint"'* ]] ||
  fail "reference: the numerical estimate's checks are not recorded: $meta"
out=$("$flexref" reference scenes/book_toss.toml --solver arkode --rtol 1e-8 --no-estimate \
  -o "$tmp/ark.csv" 2>&1) || fail "reference --solver arkode failed: $out"
[[ $out == *"arkode (erk-fehlberg-13-7-8)"* ]] || fail "reference arkode: $out"
"$flexref" reference scenes/book_toss.toml --solver cvode --method rk4 -o "$tmp/z.csv" \
  >/dev/null 2>&1 && fail "unknown --method accepted"
[[ ! -e $tmp/z.csv ]] || fail "unknown --method: an output file was written"
"$flexref" reference scenes/book_toss.toml --solver ida --method adams -o "$tmp/z.csv" \
  >/dev/null 2>&1 && fail "ida --method adams accepted"
[[ ! -e $tmp/z.csv ]] || fail "ida --method adams: an output file was written"

# A stiff oscillatory scene (undamped modes 57x the output Nyquist rate): the default reference
# is ARKODE's ESDIRK with the structured Newton systems, the choice recorded and printed;
# --solver cvode gets BDF capped at order 2.
out=$("$flexref" reference scenes/flexible_spinner_64.toml --rtol 1e-6 --no-estimate \
  -o "$tmp/s64.csv" 2>&1) || fail "reference on flexible_spinner_64 failed: $out"
[[ $out == *"arkode (esdirk547l2sa-7-4-5)"*"solver: stiff oscillatory"* ]] ||
  fail "reference flexible_spinner_64: not routed to the ESDIRK: $out"
meta=$(cat "$tmp/s64.csv.meta.toml")
[[ $meta == *'solver = "arkode"'*'solver_reason = "stiff oscillatory'*'method = "esdirk547l2sa-7-4-5"'*'jacobian = "structured'* ]] ||
  fail "reference flexible_spinner_64: the choice is not recorded: $meta"
out=$("$flexref" reference scenes/flexible_spinner_64.toml --solver cvode --rtol 1e-6 \
  --no-estimate -o "$tmp/s64c.csv" 2>&1) || fail "reference cvode on flexible_spinner_64: $out"
[[ $out == *"cvode (bdf2)"* ]] || fail "reference cvode on flexible_spinner_64: $out"
meta=$(cat "$tmp/s64c.csv.meta.toml")
[[ $meta == *'solver_reason = "chosen with --solver"'* ]] ||
  fail "reference --solver cvode: not recorded as the user's choice: $meta"

# Wear outputs (issue 13): the tube's run and reference have the wear columns, compare reports
# the wear metric; a scene without a named contact refuses it.
sed 's/^end_time = 10.0 /end_time = 0.05 /' scenes/tube_support_impact.toml >"$tmp/tube.toml"
"$flexref" run "$tmp/tube.toml" --scheme c2 --dt 1e-5 --model lte -o "$tmp/tube_run.csv" \
  >/dev/null || fail "tube run failed"
"$flexref" reference "$tmp/tube.toml" --solver cvode --rtol 1e-9 --no-estimate \
  -o "$tmp/tube_ref.csv" >/dev/null || fail "tube reference failed"
[[ $(head -1 "$tmp/tube_ref.csv") == *"support.fn,support.slip_speed,support.wear_work,support.impacts" ]] ||
  fail "tube reference lacks the wear columns: $(head -1 "$tmp/tube_ref.csv")"
out=$("$flexref" compare "$tmp/tube_run.csv" "$tmp/tube_ref.csv" --metric wear 2>&1) ||
  fail "compare --metric wear failed: $out"
[[ $out == *"metric wear"* ]] || fail "compare --metric wear: $out"
"$flexref" compare "$tmp/run.csv" "$tmp/ref.csv" --metric wear >/dev/null 2>&1 &&
  fail "compare --metric wear accepted a scene without a named contact"

if ((failures)); then
  echo "$failures CLI checks failed"
  exit 1
fi
echo "all CLI checks passed"
