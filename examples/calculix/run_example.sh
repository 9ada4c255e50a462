#!/usr/bin/env bash
# The CalculiX example (examples/calculix/README.md): mesh a steel blade (make_deck.py), compute
# its clamped modes and the free solid's matrices with CalculiX, import them as modal data, and
# spin the blade up on a hub (blade_spinup.toml) with the reference solver and a scheme.
# Usage: run_example.sh FLEXREF OUTDIR    (FLEXREF: the flexref executable)
set -euo pipefail
flexref=$(realpath "$1")
out=$2
here=$(cd "$(dirname "$0")" && pwd)
command -v ccx >/dev/null || { echo "run_example: ccx (CalculiX, Debian calculix-ccx) not found" >&2; exit 2; }
mkdir -p "$out"
cd "$out"
python3 "$here/make_deck.py" --length 0.5 --width 0.06 --thickness 0.01 --x0 0.1 \
  --nx 8 --ny 2 --nz 2 --modes 6 -o blade.inp
ccx -i blade > ccx.log 2>&1 || { cat ccx.log >&2; exit 1; }
"$flexref" import-modes blade.frd -o blade.modal.toml --modes 1-4
cp "$here/blade_spinup.toml" .
"$flexref" check blade_spinup.toml
# The coupled model by the reference solver; the LTE model by the reference solver and by C2
# (the hybrid schemes integrate the LTE model), compared.
"$flexref" reference blade_spinup.toml --rtol 1e-8 --no-estimate -o reference.csv
"$flexref" reference blade_spinup.toml --model lte --rtol 1e-10 --no-estimate -o reference_lte.csv
"$flexref" run blade_spinup.toml --model lte --scheme c2 --dt 2e-4 -o c2_lte.csv
"$flexref" compare c2_lte.csv reference_lte.csv
