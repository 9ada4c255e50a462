#!/bin/sh
# Writes the outputs of every bundled scene into a folder, for a refactor's byte-identity check:
#   scripts/checks/outputs_snapshot.sh build/app/flexref /tmp/before
#   ... change, build ...
#   scripts/checks/outputs_snapshot.sh build/app/flexref /tmp/after
#   diff -r /tmp/before /tmp/after && echo identical
# Per scene: a CVODE reference at rtol 1e-8 (the coupled model where the scene needs it),
# a C2 run at 1e-3, and for the scenes listed below generalized-α and an extended-precision
# reference. A command that fails leaves its exit status and message instead (compared too).
# The sidecars' host and time lines differ between runs, so only CSVs and messages are kept.
set -u
flexref=$1
out=$2
mkdir -p "$out"
one() {
  tag=$1
  shift
  if "$flexref" "$@" -o "$out/$tag.csv" >/dev/null 2>"$out/$tag.err"; then
    rm -f "$out/$tag.err"
  else
    echo "exit $?" >>"$out/$tag.err"
    rm -f "$out/$tag.csv"
  fi
  rm -f "$out/$tag.csv.meta.toml" "$out/$tag.meta.toml"
}
for scene in scenes/*.toml; do
  name=$(basename "$scene" .toml)
  one "$name.reference" reference "$scene" --solver cvode --rtol 1e-8 --no-estimate
  one "$name.reference_coupled" reference "$scene" --solver cvode --rtol 1e-8 --no-estimate \
    --model coupled
  one "$name.c2" run "$scene" --scheme c2 --dt 1e-3
done
for name in free_spin heavy_top double_pendulum_ideal spin_up_beam flexible_spinner; do
  [ -f "scenes/$name.toml" ] || continue
  one "$name.genalpha" run "scenes/$name.toml" --scheme genalpha --dt 1e-3
  one "$name.extended" reference "scenes/$name.toml" --precision extended --rtol 1e-12 \
    --no-estimate
done
echo "$(ls "$out" | wc -l) files in $out"
