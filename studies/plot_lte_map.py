#!/usr/bin/env python3
"""Contour map of a `flexref lte-map` study.

Usage: plot_lte_map.py lte_map.csv out.png "title" [scene_spin_ratio scene_inertia_ratio]

Reads spin_ratio,inertia_ratio,...,tip_error,...,resolved,status (one row per grid point) and
draws, on log axes, filled contours of log10 of the LTE tip-deflection error relative to the
coupled model against the spin ratio Omega0/omega1 (x) and the inertia ratio I_flex/I_rigid (y),
with the 1 %, 5 % and 20 % lines drawn and labelled. Grid points are marked: a cross where the
error is below 100x the estimated reference error (an upper bound only), a red x where the run
failed; a star at the scene's own (x, y) when given. Needs a full grid (every x at every y).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402


def main(argv):
    if len(argv) not in (4, 6):
        sys.stderr.write(__doc__)
        return 2
    rows = list(csv.DictReader(open(argv[1], newline="")))
    xs = sorted({float(r["spin_ratio"]) for r in rows})
    ys = sorted({float(r["inertia_ratio"]) for r in rows})
    if len(xs) < 2 or len(ys) < 2:
        sys.stderr.write("plot_lte_map.py: a contour map needs at least 2 spin and 2 inertia "
                         "ratios\n")
        return 1
    error = {}
    for r in rows:
        e = float(r["tip_error"]) if r["status"] == "ok" else float("nan")
        error[(float(r["spin_ratio"]), float(r["inertia_ratio"]))] = e
    z = [[error.get((x, y), float("nan")) for x in xs] for y in ys]
    # Exact zeros cannot be drawn on a log scale: floor at 1e-6 (0.0001 %).
    z = [[max(v, 1e-6) if math.isfinite(v) else float("nan") for v in row] for row in z]

    fig, ax = plt.subplots(figsize=(7.0, 5.2), dpi=120)
    finite = [v for row in z for v in row if math.isfinite(v)]
    lo = min(min(finite), 1e-3)
    hi = max(max(finite), 1.0)
    # Contours are interpolated in log10 of x, y and the error, as the table's crossings are
    # (studies/lte_map.cpp, lte_map_crossings): interpolating the raw values on log axes put the
    # 5 % line of a 2x2 map at 0.027 where the table says 0.081.
    lx = [math.log10(x) for x in xs]
    ly = [math.log10(y) for y in ys]
    lz = [[math.log10(v) if math.isfinite(v) else float("nan") for v in row] for row in z]
    levels = [k / 4.0 for k in range(math.floor(4 * math.log10(lo)),
                                     math.ceil(4 * math.log10(hi)) + 1)]
    filled = ax.contourf(lx, ly, lz, levels=levels, cmap="viridis")
    power = ticker.FuncFormatter(lambda v, _: f"{10.0 ** v:.3g}")
    bar = fig.colorbar(filled, ax=ax, format=power)
    bar.set_label("LTE tip-deflection error / max coupled deflection")
    marks = [math.log10(0.01), math.log10(0.05), math.log10(0.20)]
    lines = ax.contour(lx, ly, lz, levels=marks, colors=["white", "orange", "red"],
                       linewidths=[1.2, 2.0, 1.2])
    ax.clabel(lines, fmt={marks[0]: "1 %", marks[1]: "5 %", marks[2]: "20 %"}, fontsize=9)
    # clabel drops labels on short segments: the legend names the lines too.
    for color, width, text in (("white", 1.2, "1 % line"), ("orange", 2.0, "5 % line"),
                               ("red", 1.2, "20 % line")):
        ax.plot([], [], color=color, linewidth=width, label=text)
    unresolved = [(float(r["spin_ratio"]), float(r["inertia_ratio"])) for r in rows
                  if r["status"] == "ok" and r["resolved"] != "1"]
    failed = [(float(r["spin_ratio"]), float(r["inertia_ratio"])) for r in rows
              if r["status"] != "ok"]
    grid = [(x, y) for x in xs for y in ys]
    log = math.log10
    ax.plot([log(p[0]) for p in grid], [log(p[1]) for p in grid], ".", color="black", markersize=2,
            label="grid point")
    if unresolved:
        ax.plot([log(p[0]) for p in unresolved], [log(p[1]) for p in unresolved], "+",
                color="white", label="< 100x reference error (upper bound)")
    if failed:
        ax.plot([log(p[0]) for p in failed], [log(p[1]) for p in failed], "x", color="red",
                label="failed")
    if len(argv) == 6:
        ax.plot([log(float(argv[4]))], [log(float(argv[5]))], "*", color="magenta", markersize=12,
                markeredgecolor="black", label="the scene itself")
    # The axes hold log10 values; label them with the ratios themselves.
    ax.xaxis.set_major_formatter(power)
    ax.yaxis.set_major_formatter(power)
    ax.set_xlabel("spin ratio Ω0/ω1 (initial spin / first clamped frequency) [-]")
    ax.set_ylabel("inertia ratio I_flex/I_rigid about the spin axis [-]")
    ax.set_title(argv[3])
    legend = ax.legend(fontsize=7, loc="upper left", framealpha=0.9)
    legend.get_frame().set_facecolor("0.55")  # grey, so that the white 1 % line shows
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
