#!/usr/bin/env python3
"""Log-log work-precision plot of a `flexref work-precision` study.

Usage: plot_work_precision.py work_precision.csv out.png "title" metric
Reads the CSV written by the study (method,kind,setting,error,cpu_seconds,status) and draws,
for each scheme (solid, one point per step) and each reference solver (dashed, one point per
tolerance), the error against the CPU time; runs whose error is below what the reference can
certify are crossed out, failed runs are left out, and the target errors of the summary table
are dotted horizontal lines.
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

TARGETS = (1e-2, 1e-4, 1e-6, 1e-8)
METRIC_LABELS = {
    "rotation+points": "error (L∞ rotation [rad] + L∞ tracked points [m])",
    "rotation": "L∞ rotation error [rad]",
    "points": "L∞ tracked-point error [m]",
    "position": "L∞ position error [m]",
    "velocity": "L∞ velocity error [m/s]",
    "angular_velocity": "L∞ angular-velocity error [rad/s]",
}


def main(argv):
    if len(argv) != 5:
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
    crossed = False
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
        bad = [p for p in pts if p[2] != "ok"]
        if bad:
            ax.loglog([b[0] for b in bad], [b[1] for b in bad], linestyle="none", marker="x",
                      color="k", markersize=9,
                      label=None if crossed else "not counted: uncertified, unstable or "
                      "saturated (see status)")
            crossed = True
    for i, t in enumerate(TARGETS):
        ax.axhline(t, linestyle=":", color="gray", linewidth=0.8,
                   label="target errors" if i == 0 else None)
    ax.set_xlabel("CPU time [s] (thread CPU time of the integration, min over repeats)")
    ax.set_ylabel(METRIC_LABELS.get(argv[4], f"error ({argv[4]})"))
    ax.set_title(argv[3])
    ax.grid(True, which="both", alpha=0.3)
    legend(ax, fontsize="small")
    fig.tight_layout()
    fig.savefig(argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
