#!/usr/bin/env python3
"""Errors of a `flexref modes` study against the number of retained modes.

Usage: plot_modal_truncation.py modes.csv out.png "title"

Reads modes,omega_max,tip_error,tip_error_m,attitude_error,...,tip_estimate,attitude_estimate,
resolved,...,status (one row per mode count; the largest count is the reference, error 0) and
draws on log-log axes the relative tip-deflection error and the attitude error (rad) of each
truncation against the reference, with the estimated integration error of the runs as dashed
lines: where an error is not 10x above that floor (open markers) it is an upper bound of the
truncation error, not a measurement. Failed rows are left out.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def legend(ax, **kwargs):
    """ax.legend(**kwargs) when an artist carries a label, else None: matplotlib warns on
    standard error ("No artists with labels found") for a legend of nothing, e.g. when every
    level of a study failed."""
    if not ax.get_legend_handles_labels()[0]:
        return None
    return ax.legend(**kwargs)


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    rows = [r for r in csv.DictReader(open(argv[1], newline="")) if r["status"] == "ok"]
    if len(rows) < 2:
        sys.stderr.write("plot_modal_truncation.py: need at least two successful rows\n")
        return 1
    reference = max(int(r["modes"]) for r in rows)
    compared = [r for r in rows if int(r["modes"]) != reference]
    if not compared:
        sys.stderr.write("plot_modal_truncation.py: nothing to compare with the reference\n")
        return 1

    fig, ax = plt.subplots(figsize=(6.4, 4.6), dpi=120)
    modes = [int(r["modes"]) for r in compared]
    series = [
        ("tip_error", "tip_estimate", "tip deflection (relative)", "C0", "o"),
        ("attitude_error", "attitude_estimate", "attitude (rad)", "C1", "s"),
    ]
    for key, estimate, label, color, marker in series:
        values = [float(r[key]) for r in compared]
        resolved = [r["resolved"] == "1" for r in compared]
        positive = [(m, v, ok) for m, v, ok in zip(modes, values, resolved) if v > 0.0 and
                    math.isfinite(v)]
        if not positive:
            continue
        ax.plot([p[0] for p in positive], [p[1] for p in positive], color=color, label=label)
        for m, v, ok in positive:
            ax.plot([m], [v], marker=marker, color=color,
                    markerfacecolor=color if ok else "none", linestyle="none")
        floor = [(int(r["modes"]), float(r[estimate])) for r in rows]
        floor = [(m, v) for m, v in floor if v > 0.0 and math.isfinite(v)]
        if floor:
            ax.plot([f[0] for f in floor], [f[1] for f in floor], color=color, linestyle="--",
                    linewidth=0.8, label=label.split(" (")[0] + ": integration error estimate")
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xticks(sorted({int(r["modes"]) for r in rows}))
    ax.get_xaxis().set_major_formatter(plt.ScalarFormatter())
    ax.set_xlabel("retained modes (reference: %d)" % reference)
    ax.set_ylabel("max over the outputs of the error against the reference")
    ax.set_title(argv[3], fontsize=10)
    ax.grid(True, which="both", linewidth=0.3)
    legend(ax, fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
