#!/usr/bin/env python3
"""Log-log convergence plot of a `flexref converge` study.

Usage: plot_convergence.py convergence.csv out.png "title" [step_limit "what limits it"
                           ["orders" ["metric" "unit" "terms"]]]
Reads the CSV written by the study (scheme,h,steps,error,order,cpu_seconds,status), draws the
error of each scheme against its step, marks the levels that were not used in the fit with one
marker per reason (saturated, unstable, uncertified, other: plot_status.py) and a legend entry
for each, adds reference slopes 1 and 2 a factor 3 below every drawn level (so that no curve
hides them), and draws the scene's explicit step limit 2/omega when one is given (a number;
"inf": none). `orders` is "scheme=observed" pairs separated by commas (observed: the fitted
order, or why there is none), shown in the legend. `metric`, `unit` and `terms` (the study's
metric, its unit and what it is taken from: trajectory/error_metrics.hpp) label the error axis.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plot_status  # noqa: E402  (beside this script)

# The guides lie at least this factor below every drawn level.
GUIDE_OFFSET = 3.0


def parse_orders(text):
    orders = {}
    for pair in filter(None, text.split(",")):
        scheme, _, observed = pair.partition("=")
        orders[scheme] = observed
    return orders


def legend(ax, **kwargs):
    """ax.legend(**kwargs) when an artist carries a label, else None: matplotlib warns on
    standard error ("No artists with labels found") for a legend of nothing, e.g. when every
    level of a study failed."""
    if not ax.get_legend_handles_labels()[0]:
        return None
    return ax.legend(**kwargs)


def main(argv):
    if len(argv) not in (4, 6, 7, 10):
        sys.stderr.write(__doc__)
        return 2
    rows = list(csv.DictReader(open(argv[1], newline="")))
    orders = parse_orders(argv[6]) if len(argv) >= 7 else {}
    schemes = []
    for r in rows:
        if r["scheme"] not in schemes:
            schemes.append(r["scheme"])
    fig, ax = plt.subplots(figsize=(8.8, 4.8), dpi=120)
    markers = "osD^v<>"
    drawn = []  # (h, error) of every level drawn
    present = {}  # the reasons of the levels left out of the fit (plot_status.mark)
    for k, s in enumerate(schemes):
        pts = [(float(r["h"]), float(r["error"]), r["status"]) for r in rows if r["scheme"] == s]
        pts = [p for p in pts if math.isfinite(p[1]) and p[1] > 0]
        if not pts:
            continue
        label = s.upper()
        if s in orders:
            observed = orders[s]
            try:
                label += f" (observed order {float(observed):.2f})"
            except ValueError:
                label += f" ({observed})"
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=markers[k % len(markers)],
                  label=label)
        plot_status.merge(present, plot_status.mark(ax, pts))
        drawn += [(p[0], p[1]) for p in pts]
    plot_status.legend_entries(ax, present)
    if drawn:
        hs = sorted({h for h, _ in drawn})
        for p, style in ((1, ":"), (2, "--")):
            # c·h^p at most every drawn error / GUIDE_OFFSET: below all curves, never hidden.
            c = min(e / h ** p for h, e in drawn) / GUIDE_OFFSET
            ax.loglog(hs, [c * h ** p for h in hs], style, color="gray", linewidth=1.5,
                      label=f"slope {p}")
    if len(argv) >= 6 and math.isfinite(float(argv[4])) and rows:
        limit = float(argv[4])
        label = f"explicit step limit 2/ω = {limit:.3g} s ({argv[5]})"
        hs = [float(r["h"]) for r in rows]
        if min(hs) / 10 <= limit <= max(hs) * 10:
            ax.axvline(limit, color="tab:red", linestyle="-.", linewidth=1.2, label=label)
        else:  # far outside the steps: say it without stretching the axis
            ax.plot([], [], " ", label=label)
    ax.set_xlabel("step h [s]")
    ax.set_ylabel(plot_status.error_label(*argv[7:10]) if len(argv) == 10 else "error")
    ax.set_title(argv[3])
    ax.grid(True, which="both", alpha=0.3)
    # Beside the axes: inside, it hides a curve wherever it is put.
    legend(ax, fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
