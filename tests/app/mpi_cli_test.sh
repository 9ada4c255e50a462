#!/usr/bin/env bash
# The studies distributed over MPI ranks (docs/mpi.md): results identical to the serial run,
# rank 0 alone writes and reports, failures end every rank. Usage: mpi_cli_test.sh FLEXREF MPIEXEC
set -uo pipefail
flexref=$1
mpiexec=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpi=("$mpiexec" -n 2 --oversubscribe)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# Runs the same study serially and on two ranks; the named CSVs must be byte-identical
# (columns of CPU times removed by the optional cut expression).
same() {
  local name=$1 csvs=$2
  shift 2
  "$flexref" "$@" --out "$tmp/$name.serial" >"$tmp/$name.serial.log" 2>&1 ||
    { fail "$name: serial run failed"; cat "$tmp/$name.serial.log"; return; }
  "${mpi[@]}" "$flexref" "$@" --out "$tmp/$name.mpi" >"$tmp/$name.mpi.log" 2>&1 ||
    { fail "$name: 2-rank run failed"; cat "$tmp/$name.mpi.log"; return; }
  for csv in $csvs; do
    cmp -s "$tmp/$name.serial/$csv" "$tmp/$name.mpi/$csv" || fail "$name: $csv differs serial vs 2 ranks"
  done
  grep -q '^\[run\]' "$tmp/$name.mpi/study.toml" && grep -q '^processes = 2' "$tmp/$name.mpi/study.toml" ||
    fail "$name: study.toml does not record the 2 processes"
  [[ $(grep -c "^wrote " "$tmp/$name.mpi.log") == 1 ]] || fail "$name: the result is not reported once"
  ls "${TMPDIR:-/tmp}" | grep -q "^flexref-rank-" &&
    fail "$name: a rank's private staging folder was left in the temporary folder"
  echo "ok: $name"
}

same lte_map "lte_map.csv" lte-map scenes/flexible_spinner.toml --spin-ratios 0.02,0.2,0.5 \
  --inertia-ratios 0.01,1 --end-time 1.5 --jobs 1
# The opening line says who works: the ranks and their threads ("on 1 threads" before).
grep -q "on 2 processes x 1 thread each" "$tmp/lte_map.mpi.log" ||
  fail "lte_map: the 2-rank log does not say it runs on 2 processes: $(head -3 "$tmp/lte_map.mpi.log")"
same stability "stability.csv long_run.csv" stability --count 4 --steps 300 --long-run-steps 400 \
  --jobs 1
same stability_modal "stability.csv" stability --parameter modal_frequency --values 50,500 \
  --steps 400 --jobs 1
# converge: the CPU-time column differs from run to run, the rest must not.
same converge "" converge scenes/free_spin.toml --levels 3 --dt 0.02 --jobs 1
cut -d, -f1-5,7 "$tmp/converge.serial/convergence.csv" >"$tmp/a.csv"
cut -d, -f1-5,7 "$tmp/converge.mpi/convergence.csv" >"$tmp/b.csv"
cmp -s "$tmp/a.csv" "$tmp/b.csv" || fail "converge: errors differ serial vs 2 ranks"
# converge --external: every level's file is kept in the study folder, whichever rank ran it.
sed 's/^end_time = 100.0 /end_time = 2.0 /' scenes/free_spin.toml >"$tmp/fs2.toml"
same external "run_euler_0.csv run_euler_1.csv run_euler_2.csv" converge "$tmp/fs2.toml" \
  --external "/usr/bin/python3 examples/external/lie_euler.py {scene} {dt} {output}" \
  --label euler --order 1 --dt 0.02 --levels 3 --jobs 1
cut -d, -f1-5,7 "$tmp/external.serial/convergence.csv" >"$tmp/a.csv"
cut -d, -f1-5,7 "$tmp/external.mpi/convergence.csv" >"$tmp/b.csv"
cmp -s "$tmp/a.csv" "$tmp/b.csv" || fail "converge --external: errors differ serial vs 2 ranks"
# modes: the runs' responses travel between ranks (the comparisons read them on every rank);
# the cpu_seconds column (11) differs from run to run.
same modes "" modes scenes/flexible_spinner.toml --modes 2,4 --end-time 0.5 --jobs 1
cut -d, -f1-10,12 "$tmp/modes.serial/modes.csv" >"$tmp/a.csv"
cut -d, -f1-10,12 "$tmp/modes.mpi/modes.csv" >"$tmp/b.csv"
cmp -s "$tmp/a.csv" "$tmp/b.csv" || fail "modes: rows differ serial vs 2 ranks"

# Bad input on every rank: one message, exit code 1, no hang.
"${mpi[@]}" "$flexref" lte-map scenes/no_such_scene.toml --out "$tmp/x" >"$tmp/bad.log" 2>&1
code=$?
[[ $code == 1 ]] || fail "bad scene: exit code $code, expected 1"
[[ $(grep -c "flexref: error:" "$tmp/bad.log") == 1 ]] || { fail "bad scene: not reported once"; cat "$tmp/bad.log"; }
# An output folder only rank 0 checks: its failure ends both ranks.
touch "$tmp/file"
"${mpi[@]}" "$flexref" stability --count 2 --steps 100 --no-degenerate --out "$tmp/file/sub" \
  >"$tmp/out.log" 2>&1
code=$?
[[ $code != 0 ]] || fail "bad --out: exit code 0"
[[ $(grep -c "cannot write the output folder" "$tmp/out.log") == 1 ]] ||
  { fail "bad --out: not reported once"; cat "$tmp/out.log"; }

if ((failures)); then
  echo "$failures failure(s)"
  exit 1
fi
echo "all MPI command-line checks passed"
