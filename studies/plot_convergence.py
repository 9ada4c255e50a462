#!/usr/bin/env python3
"""Log-log convergence plot of a `flexref converge` study.

Usage: plot_convergence.py convergence.csv out.png "title" [step_limit "what limits it"]
Reads the CSV written by the study (scheme,h,steps,error,order,cpu_seconds,status), draws the
error of each scheme against its step, marks levels that were not used in the fit (a legend
entry says so), adds reference slopes 1 and 2 anchored at the coarsest certified point, and
draws the scene's explicit step limit 2/omega when one is given (a number; "inf": none).
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
    if len(argv) not in (4, 6):
        sys.stderr.write(__doc__)
        return 2
    rows = list(csv.DictReader(open(argv[1], newline="")))
    schemes = []
    for r in rows:
        if r["scheme"] not in schemes:
            schemes.append(r["scheme"])
    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=120)
    markers = "osD^v<>"
    anchor = None
    unused_labelled = False
    for k, s in enumerate(schemes):
        pts = [(float(r["h"]), float(r["error"]), r["status"]) for r in rows if r["scheme"] == s]
        pts = [p for p in pts if math.isfinite(p[1]) and p[1] > 0]
        if not pts:
            continue
        h = [p[0] for p in pts]
        e = [p[1] for p in pts]
        line, = ax.loglog(h, e, marker=markers[k % len(markers)], label=s.upper())
        bad = [(p[0], p[1]) for p in pts if p[2] != "ok"]
        if bad:
            ax.loglog([b[0] for b in bad], [b[1] for b in bad], linestyle="none", marker="x",
                      color="k", markersize=9,
                      label=None if unused_labelled else "not in the fit (see status)")
            unused_labelled = True
        ok = [p for p in pts if p[2] == "ok"]
        if ok and (anchor is None or ok[0][1] > anchor[1]):
            anchor = ok[0]
    if anchor is not None:
        hs = sorted({float(r["h"]) for r in rows})
        for p, style in ((1, ":"), (2, "--")):
            ax.loglog(hs, [anchor[1] * (x / anchor[0]) ** p for x in hs], style, color="gray",
                      label=f"slope {p}")
    if len(argv) == 6 and math.isfinite(float(argv[4])) and rows:
        limit = float(argv[4])
        label = f"explicit step limit 2/ω = {limit:.3g} s ({argv[5]})"
        hs = [float(r["h"]) for r in rows]
        if min(hs) / 10 <= limit <= max(hs) * 10:
            ax.axvline(limit, color="tab:red", linestyle="-.", linewidth=1.2, label=label)
        else:  # far outside the steps: say it without stretching the axis
            ax.plot([], [], " ", label=label)
    ax.set_xlabel("step h [s]")
    ax.set_ylabel("error (L∞ rotation [rad] + L∞ tracked points [m])")
    ax.set_title(argv[3])
    ax.grid(True, which="both", alpha=0.3)
    legend(ax)
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
