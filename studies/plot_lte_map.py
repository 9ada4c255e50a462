#!/usr/bin/env python3
"""Contour maps of a `flexref lte-map` study.

Usage: plot_lte_map.py lte_map.csv out.png "title" [scene_spin_ratio scene_inertia_ratio]

Reads one row per grid point (spin_ratio, inertia_ratio, tip_error, envelope_error,
frequency_shift, classical_tip_error, classical_envelope_error, classical_frequency_shift,
resolved, classical_resolved, status) and draws, on log axes of the spin ratio Omega0/omega1 (x)
and the inertia ratio I_flex/I_rigid (y), one panel per simplification (rows: LTE, and the
classical coupled model when the truth is the stiffened model) and metric (columns: L-inf tip
error over the horizon, peak deflection error, first-mode frequency shift): filled contours of
log10 of the metric's absolute value relative to the truth, with the 1 %, 5 % and 20 % lines
drawn and labelled. Grid points are marked: a cross where the tip error is below 100x the
estimated reference error (an upper bound only), a red x where the run failed; a star at the
scene's own (x, y) when given. Needs a full grid (every x at every y).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402


def legend(ax, **kwargs):
    """ax.legend(**kwargs) when an artist carries a label, else None: matplotlib warns on
    standard error ("No artists with labels found") for a legend of nothing, e.g. when every
    level of a study failed."""
    if not ax.get_legend_handles_labels()[0]:
        return None
    return ax.legend(**kwargs)

METRICS = (("tip_error", "L∞ tip error"), ("envelope_error", "peak deflection error"),
           ("frequency_shift", "first-mode frequency shift"))


def failed(row):
    return row["status"].startswith("failed")


def value(row, key):
    """|row[key]|, or NaN for a failed point or a value the study did not measure (an empty
    cell: a classical column of a two-level map, a frequency the status says is missing)."""
    if failed(row):
        return float("nan")
    try:
        v = abs(float(row[key]))
    except (KeyError, ValueError):
        return float("nan")
    return v if math.isfinite(v) else float("nan")


def grid_ticks(values, most=6):
    """Tick positions (log10) at grid values, both ends included, at most `most` of them."""
    m = min(len(values), most)
    if m < 2:
        return [math.log10(v) for v in values]
    picked = sorted({math.floor(i * (len(values) - 1) / (m - 1) + 0.5) for i in range(m)})
    return [math.log10(values[i]) for i in picked]


def panel(fig, ax, rows, xs, ys, key, title, resolved_key, scene):
    log = math.log10
    data = {(float(r["spin_ratio"]), float(r["inertia_ratio"])): value(r, key) for r in rows}
    # Exact zeros cannot be drawn on a log scale: floor at 1e-6 (0.0001 %).
    z = [[max(data.get((x, y), float("nan")), 1e-6) for x in xs] for y in ys]
    finite = [v for row in z for v in row if math.isfinite(v)]
    power = ticker.FuncFormatter(lambda v, _: f"{10.0 ** v:.3g}")
    lx = [log(x) for x in xs]
    ly = [log(y) for y in ys]
    if finite:
        lo = min(min(finite), 1e-3)
        hi = max(max(finite), 1.0)
        # Interpolated in log10 of x, y and the metric, as the table's crossings are
        # (studies/lte_map.cpp, lte_map_crossings).
        lz = [[log(v) if math.isfinite(v) else float("nan") for v in row] for row in z]
        levels = [k / 4.0 for k in range(math.floor(4 * log(lo)), math.ceil(4 * log(hi)) + 1)]
        filled = ax.contourf(lx, ly, lz, levels=levels, cmap="viridis")
        bar = fig.colorbar(filled, ax=ax, format=power)
        bar.set_label("|metric| relative to the truth", fontsize=7)
        marks = [log(0.01), log(0.05), log(0.20)]
        lines = ax.contour(lx, ly, lz, levels=marks, colors=["white", "orange", "red"],
                           linewidths=[1.2, 2.0, 1.2])
        ax.clabel(lines, fmt={marks[0]: "1 %", marks[1]: "5 %", marks[2]: "20 %"}, fontsize=8)
    else:
        ax.text(0.5, 0.5, "no value", transform=ax.transAxes, ha="center")
    for color, width, text in (("white", 1.2, "1 % line"), ("orange", 2.0, "5 % line"),
                               ("red", 1.2, "20 % line")):
        ax.plot([], [], color=color, linewidth=width, label=text)
    grid = [(x, y) for x in xs for y in ys]
    ax.plot([log(p[0]) for p in grid], [log(p[1]) for p in grid], ".", color="black",
            markersize=2, label="grid point")
    unresolved = [(float(r["spin_ratio"]), float(r["inertia_ratio"])) for r in rows
                  if not failed(r) and r.get(resolved_key, "1") != "1"]
    failures = [(float(r["spin_ratio"]), float(r["inertia_ratio"])) for r in rows if failed(r)]
    missing = [(float(r["spin_ratio"]), float(r["inertia_ratio"])) for r in rows
               if not failed(r) and math.isnan(value(r, key))]
    if unresolved and key.endswith("tip_error"):
        ax.plot([log(p[0]) for p in unresolved], [log(p[1]) for p in unresolved], "+",
                color="white", label="< 100x reference error")
    if failures:
        ax.plot([log(p[0]) for p in failures], [log(p[1]) for p in failures], "x", color="red",
                label="failed")
    if missing:
        ax.plot([log(p[0]) for p in missing], [log(p[1]) for p in missing], "o",
                markerfacecolor="none", color="red", markersize=5, label="not measured (status)")
    if scene:
        ax.plot([log(scene[0])], [log(scene[1])], "*", color="magenta", markersize=11,
                markeredgecolor="black", label="the scene")
    # Ticks at grid values, the grid's ends included.
    ax.xaxis.set_major_locator(ticker.FixedLocator(grid_ticks(xs, 5)))
    ax.yaxis.set_major_locator(ticker.FixedLocator(grid_ticks(ys, 6)))
    ax.xaxis.set_major_formatter(power)
    ax.yaxis.set_major_formatter(power)
    ax.set_xlabel("spin ratio Ω0/ω1 [-]", fontsize=8)
    ax.set_ylabel("inertia ratio I_flex/I_rigid [-]", fontsize=8)
    ax.set_title(title, fontsize=9)
    ax.tick_params(labelsize=7)


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
    scene = (float(argv[4]), float(argv[5])) if len(argv) == 6 else None
    classical = any(math.isfinite(value(r, "classical_tip_error")) for r in rows)
    models = [("", "LTE", "resolved")]
    if classical:
        models.append(("classical_", "classical coupled", "classical_resolved"))
    fig, axes = plt.subplots(len(models), 3, figsize=(15.0, 4.4 * len(models)), dpi=100,
                             squeeze=False)
    for i, (prefix, name, resolved_key) in enumerate(models):
        for j, (key, metric) in enumerate(METRICS):
            panel(fig, axes[i][j], rows, xs, ys, prefix + key, f"{name}: {metric}", resolved_key,
                  scene)
    box = legend(axes[0][0], fontsize=6, loc="upper left", framealpha=0.9)
    if box is not None:
        box.get_frame().set_facecolor("0.55")  # grey, so that the white 1 % line shows
    fig.suptitle(argv[3], fontsize=11)
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
