#!/usr/bin/env python3
"""Plots of a `flexref stability` study.

Usage:
  plot_stability.py sweep stability.csv out.png "title"
  plot_stability.py long_run long_run.csv out.png "title"
  plot_stability.py linear stability.csv out.png "title"

sweep: reads scheme,parameter,value,h_max,h_max_times_spin,classification and draws, log-log,
the largest stable step h_max of each scheme against the swept parameter (the rows of the
degenerate set, whose parameter is a body name, are left to the table). Guides: h|W0| = 2,
the central-difference limit of a linear oscillator at the spin frequency, and h|W0| = pi,
a rotation of pi per step. A free rigid body has no exact central-difference limit: these are
orientation marks, not theorems.

linear: reads scheme,parameter,value,omega,h_max,h_theory,... (modal_frequency or
contact_stiffness sweeps) and draws h_max of each scheme against the swept value, log-log,
with the theoretical central-difference limit 2/omega as a dashed line.

long_run: reads scheme,step,t,energy_drift,momentum_drift,quaternion_norm_drift,status and
draws the three drifts (maximum over each sampling interval) of each scheme against time.
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


def ordered(values):
    out = []
    for v in values:
        if v not in out:
            out.append(v)
    return out


def plot_sweep(rows, png, title):
    swept = [r for r in rows if r["parameter"] in ("spin", "inertia_ratio")]
    if not swept:
        sys.stderr.write("plot_stability.py: no sweep rows\n")
        return 1
    parameter = swept[0]["parameter"]
    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=120)
    markers = "osD^v<>"
    for k, s in enumerate(ordered(r["scheme"] for r in swept)):
        pts = [(float(r["value"]), float(r["h_max"])) for r in swept if r["scheme"] == s]
        pts = [p for p in pts if p[1] > 0 and math.isfinite(p[1])]
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=markers[k % len(markers)],
                      label=s.upper())
    values = sorted({float(r["value"]) for r in swept})
    if parameter == "spin":
        spins = values
        ax.set_xlabel("spin rate |W0| [rad/s]")
    else:
        # One spin for the whole ratio sweep: |W0| = (h_max |W0|) / h_max.
        r0 = next(r for r in swept if float(r["h_max"]) > 0)
        spin = float(r0["h_max_times_spin"]) / float(r0["h_max"])
        spins = [spin for _ in values]
        ax.set_xlabel("inertia ratio J3/J1")
    for c, style, text in ((math.pi, "--", "h|W0| = π (rotation π per step)"),
                           (2.0, ":", "h|W0| = 2 (central-difference limit at ω = |W0|)")):
        ax.loglog(values, [c / w for w in spins], style, color="gray", label=text)
    ax.set_ylabel("largest stable step h_max [s]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    legend(ax, fontsize=8)
    fig.tight_layout()
    fig.savefig(png)
    return 0


def plot_long_run(rows, png, title):
    columns = (("energy_drift", "|E − E0| / E0"), ("momentum_drift", "|π − π0| / |π0|"),
               ("quaternion_norm_drift", "| |θ| − 1 |"))
    fig, axes = plt.subplots(3, 1, figsize=(6.4, 8.0), dpi=120, sharex=True)
    for s in ordered(r["scheme"] for r in rows):
        mine = [r for r in rows if r["scheme"] == s]
        t = [float(r["t"]) for r in mine]
        for ax, (key, _) in zip(axes, columns):
            # Exact zeros (an invariant kept to the last bit) are drawn at 1e-17.
            ax.semilogy(t, [max(float(r[key]), 1e-17) for r in mine], label=s.upper())
    # A drift at round-off flips between ε/2 and ε from sample to sample: on an axis spanning
    # only that factor 2 it is a block of noise. Span at least 1e-17 … 1e-12 and mark ε.
    eps = 2.220446049250313e-16
    for ax, (_, label) in zip(axes, columns):
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        low, high = ax.get_ylim()
        ax.set_ylim(min(low, 1e-17), max(high, 1e-12))
        ax.axhline(eps, color="gray", linestyle=":", linewidth=1.0)
    axes[-1].text(0.01, eps * 1.5, "ε = 2.2e-16 (round-off)", color="gray", fontsize=8,
                  transform=axes[-1].get_yaxis_transform())
    axes[0].set_title(title)
    legend(axes[0])
    axes[-1].set_xlabel("time t [s]")
    fig.tight_layout()
    fig.savefig(png)
    return 0


def plot_linear(rows, png, title):
    if not rows:
        sys.stderr.write("plot_stability.py: no rows\n")
        return 1
    parameter = rows[0]["parameter"]
    xlabel = {"modal_frequency": "highest modal frequency omega_max [rad/s]",
              "contact_stiffness": "contact stiffness k [N/m]"}.get(parameter, parameter)
    fig, ax = plt.subplots(figsize=(7, 5))
    theory = sorted({(float(r["value"]), float(r["h_theory"])) for r in rows})
    ax.loglog([t[0] for t in theory], [t[1] for t in theory], "k--", linewidth=1.0,
              label="2/omega (central differences)")
    markers = {"c1": "o", "c2": "s", "nmb": "^"}
    for scheme in ordered(r["scheme"] for r in rows):
        pts = sorted((float(r["value"]), float(r["h_max"])) for r in rows
                     if r["scheme"] == scheme)
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker=markers.get(scheme, "x"),
                  linestyle="none", label=scheme.upper())
    ax.set_xlabel(xlabel)
    ax.set_ylabel("largest stable step h_max [s]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    legend(ax)
    fig.tight_layout()
    fig.savefig(png)
    return 0


def main(argv):
    if len(argv) != 5 or argv[1] not in ("sweep", "long_run", "linear"):
        sys.stderr.write(__doc__)
        return 2
    rows = list(csv.DictReader(open(argv[2], newline="")))
    if argv[1] == "sweep":
        return plot_sweep(rows, argv[3], argv[4])
    if argv[1] == "linear":
        return plot_linear(rows, argv[3], argv[4])
    return plot_long_run(rows, argv[3], argv[4])


if __name__ == "__main__":
    sys.exit(main(sys.argv))
