#!/usr/bin/env python3
"""Log-log work-precision plot of a `flexref work-precision` study.

Usage: plot_work_precision.py work_precision.csv out.png "title" metric "unit" "terms"
Reads the CSV written by the study (method,kind,setting,error,cpu_seconds,status) and draws,
for each scheme (solid, one point per step) and each reference solver (dashed, one point per
tolerance), the error against the CPU time; runs the cheapest-method table does not count are
marked with one marker per reason (saturated, unstable, uncertified, other: plot_status.py),
failed runs are left out, and the target errors of the summary table are dotted horizontal
lines. `metric`, `unit` and `terms` (trajectory/error_metrics.hpp: metric_unit, metric_terms)
label the error axis.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plot_status  # noqa: E402  (beside this script)


def legend(ax, **kwargs):
    """ax.legend(**kwargs) when an artist carries a label, else None: matplotlib warns on
    standard error ("No artists with labels found") for a legend of nothing, e.g. when every
    level of a study failed."""
    if not ax.get_legend_handles_labels()[0]:
        return None
    return ax.legend(**kwargs)

TARGETS = (1e-2, 1e-4, 1e-6, 1e-8)


def main(argv):
    if len(argv) != 7:
        sys.stderr.write(__doc__)
        return 2
    rows = list(csv.DictReader(open(argv[1], newline="")))
    methods = []
    for r in rows:
        key = (r["method"], r["kind"])
        if key not in methods:
            methods.append(key)
    fig, ax = plt.subplots(figsize=(7.2, 5.4), dpi=120)
    markers = "osD^v<>ph"
    present = {}  # the reasons of the runs not counted (plot_status.mark)
    for k, (method, kind) in enumerate(methods):
        pts = []
        for r in rows:
            if (r["method"], r["kind"]) != (method, kind) or r["status"].startswith("failed"):
                continue
            cpu, err = float(r["cpu_seconds"]), float(r["error"])
            if math.isfinite(cpu) and cpu > 0 and math.isfinite(err) and err > 0:
                pts.append((cpu, err, r["status"]))
        if not pts:
            continue
        label = method.upper() if kind != "solver" else f"{method} (rtol sweep)"
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=markers[k % len(markers)],
                  linestyle="-" if kind != "solver" else "--", label=label)
        plot_status.merge(present, plot_status.mark(ax, pts))
    plot_status.legend_entries(ax, present)
    for i, t in enumerate(TARGETS):
        ax.axhline(t, linestyle=":", color="gray", linewidth=0.8,
                   label="target errors" if i == 0 else None)
    ax.set_xlabel("CPU time [s] (thread CPU time of the integration, min over repeats)")
    ax.set_ylabel(plot_status.error_label(*argv[4:7]))
    ax.set_title(argv[3])
    ax.grid(True, which="both", alpha=0.3)
    legend(ax, fontsize="small")
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
