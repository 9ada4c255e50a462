#!/usr/bin/env bash
# The main job: set up, build the command line only, and run the `converge` study on the bundled
# book toss scene. Ends with the table of observed orders and out/converge/convergence.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --target flexref
./build/app/flexref converge scenes/book_toss.toml --schemes c1,c2,nmb --dt 1e-2 --levels 6 \
  --out out/converge
