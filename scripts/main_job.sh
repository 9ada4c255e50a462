#!/usr/bin/env bash
# The main job: set up, build the command line only, and run the `converge` study on the bundled
# book toss scene. Ends with the table of observed orders and out/converge/convergence.png.
# Eight levels (h = 1e-2 … 7.8e-5): C2's errors saturate down to h = 6.25e-4 (its tumble goes
# the wrong way, docs/schemes.md), so it needs the three finer levels to have an order at all;
# the double reference certifies every level but NMB's three finest and C1's finest and says so, where auto's
# quad reference would add ~9 s to the ~4 s study (docs/decisions.md, "The main job").
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --target flexref
./build/app/flexref converge scenes/book_toss.toml --schemes c1,c2,nmb --dt 1e-2 --levels 8 \
  --reference-precision double --out out/converge
