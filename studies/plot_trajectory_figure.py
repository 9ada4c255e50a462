#!/usr/bin/env python3
"""Plot of a `flexref figure` study (the paper's Figs. 1-3).

Usage:
  plot_trajectory_figure.py figure.csv out.png "title"

Reads curve,scheme,step,t,x,y,z (long format: one row per time and curve; the reference curve
has an empty scheme) and draws, for each step (one row of panels), the x, y and z world
coordinates of the tracked point against time: the reference as a thick grey line and C1, C2
and NMB on the same axes. A curve that stopped early (a failed run) simply ends; the table
printed by flexref says where and why.
"""
import csv
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

COLORS = {"c1": "tab:blue", "c2": "tab:orange", "nmb": "tab:green"}


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    path, png, title = argv[1], argv[2], argv[3]
    curves = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (row["curve"], row["scheme"], row["step"])
            c = curves.setdefault(key, {"t": [], "x": [], "y": [], "z": []})
            for k in ("t", "x", "y", "z"):
                c[k].append(float(row[k]))
    reference = [v for (name, scheme, step), v in curves.items() if scheme == ""]
    steps = []
    for (name, scheme, step) in curves:
        if scheme and step not in steps:
            steps.append(step)
    if not reference or not steps:
        sys.stderr.write("plot_trajectory_figure.py: no reference or no scheme curves\n")
        return 1
    ref = reference[0]
    fig, axes = plt.subplots(len(steps), 3, figsize=(13, 3.2 * len(steps)), squeeze=False,
                             sharex=True)
    for i, step in enumerate(steps):
        for j, comp in enumerate(("x", "y", "z")):
            ax = axes[i][j]
            ax.plot(ref["t"], ref[comp], color="0.6", linewidth=3.0, label="reference")
            for (name, scheme, s), c in curves.items():
                if scheme and s == step:
                    ax.plot(c["t"], c[comp], color=COLORS.get(scheme), linewidth=1.0,
                            label=scheme.upper())
            ax.set_ylabel(f"{comp} [m]  (h = {step} s)" if j == 0 else f"{comp} [m]")
            ax.grid(True, alpha=0.3)
            if i == len(steps) - 1:
                ax.set_xlabel("t [s]")
    legend(axes[0][0], loc="best", fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
