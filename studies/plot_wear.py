#!/usr/bin/env python3
"""Figures of the wear commands (docs/wear.md).

Usage:
  plot_wear.py depth wear_depth.csv out.png "title" [reference.csv]
      the largest worn depth of each contact against slow time (wear_depth.csv of `flexref
      wear`); reference.csv (t,max_depth) adds the fully coupled reference as a line.
  plot_wear.py profile wear_profile.csv out.png "title"
      the worn profile at the end: for a gap support a polar plot of the depth around the hole
      (angle about the support's axis, docs/wear.md), for point contacts a bar per point; a
      reference_depth column is drawn dashed.
  plot_wear.py jump wear_jump.csv out.png "title" [wear_jump_distances.csv]
      `flexref wear-jump`: the final profile's error against the reference (left, solid) and the
      speed-up (right) against the jump, one line per slow-time integrator and window; open
      markers for levels that are not `ok` (unresolved, regime change, unstable), failed levels
      left out. The distances file adds the distances between successive levels (dashed, at the
      coarser jump; open markers where left out of the order) and each integrator's averaging
      error, its limit's distance to the reference (dotted horizontal).
"""
import csv
import math
import sys

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def legend(ax, **kwargs):
    """ax.legend(**kwargs) when an artist carries a label (matplotlib warns on an empty one)."""
    if not ax.get_legend_handles_labels()[0]:
        return None
    return ax.legend(**kwargs)


def depth_figure(rows, png, title, reference):
    fig, ax = plt.subplots(figsize=(7, 4.2))
    contacts = [c[: -len(".wear_depth")] for c in rows[0].keys() if c.endswith(".wear_depth")]
    t = [float(r["slow_time"]) for r in rows]
    for c in contacts:
        ax.plot(t, [1e3 * float(r[c + ".wear_depth"]) for r in rows], "o-", label=c + " (multi-scale)")
    if reference:
        ax.plot(
            [float(r["t"]) for r in reference],
            [1e3 * float(r["max_depth"]) for r in reference],
            "k--",
            lw=1,
            label="fully coupled reference",
        )
    ax.set_xlabel("slow time [s]")
    ax.set_ylabel("largest worn depth [mm]")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    legend(ax, fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def profile_figure(rows, png, title):
    contacts = []
    for r in rows:
        if r["contact"] not in contacts:
            contacts.append(r["contact"])
    fig = plt.figure(figsize=(5.2 * len(contacts), 5))
    for i, c in enumerate(contacts):
        mine = [r for r in rows if r["contact"] == c]
        sectors = mine[0]["angle_deg"] != ""
        has_reference = "reference_depth" in mine[0]
        if sectors:
            ax = fig.add_subplot(1, len(contacts), i + 1, projection="polar")
            angles = [math.radians(float(r["angle_deg"])) for r in mine]
            closed = angles + angles[:1]
            depth = [1e6 * float(r["depth"]) for r in mine]
            ax.plot(closed, depth + depth[:1], "o-", ms=3, label="multi-scale")
            if has_reference:
                ref = [1e6 * float(r["reference_depth"]) for r in mine]
                ax.plot(closed, ref + ref[:1], "k--", lw=1, label="reference")
            ax.set_title(c + ": worn depth [µm] around the hole", fontsize=9)
        else:
            ax = fig.add_subplot(1, len(contacts), i + 1)
            x = [int(r["index"]) for r in mine]
            ax.bar(x, [1e6 * float(r["depth"]) for r in mine], width=0.6, label="multi-scale")
            if has_reference:
                ax.plot(x, [1e6 * float(r["reference_depth"]) for r in mine], "k_", ms=20, label="reference")
            ax.set_xlabel("point")
            ax.set_ylabel("worn depth [µm]")
            ax.set_title(c, fontsize=9)
        legend(ax, fontsize=7, loc="lower right")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def log_axes_plain(ax):
    """Jumps and speed-ups as plain numbers on the log axes (not 2x10^0)."""
    fmt = matplotlib.ticker.FuncFormatter(lambda v, _: "%g" % v)
    ax.xaxis.set_major_formatter(fmt)
    ax.xaxis.set_minor_formatter(fmt)


def jump_figure(rows, png, title, distances):
    rows = [r for r in rows if not r["status"].startswith("failed")]
    if not rows:
        sys.stderr.write("plot_wear.py: no successful level\n")
        return 1
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
    series = {}
    for r in rows:
        series.setdefault((r["slow"], r["window"]), []).append(r)
    several_windows = len({w for _, w in series}) > 1
    for (slow, window), rs in series.items():
        rs.sort(key=lambda r: float(r["jump"]))
        label = slow + (" (window %s s)" % window if several_windows else "")
        d = [float(r["jump"]) for r in rs]
        line = left.loglog(d, [float(r["error"]) for r in rs], "-", label=label)[0]
        for r in rs:
            filled = r["status"] == "ok"
            left.loglog(
                float(r["jump"]),
                float(r["error"]),
                "o",
                color=line.get_color(),
                mfc=line.get_color() if filled else "none",
            )
        right.loglog(d, [float(r["speedup"]) for r in rs], "o-", color=line.get_color(), label=label)
        mine = [x for x in distances if x["slow"] == slow and x["window"] == window]
        if mine:
            mine.sort(key=lambda x: float(x["coarse"]))
            left.loglog(
                [float(x["coarse"]) for x in mine],
                [float(x["distance"]) for x in mine],
                "--",
                color=line.get_color(),
                lw=1,
                label=label + ": distance to the next level",
            )
            for x in mine:
                left.loglog(
                    float(x["coarse"]),
                    float(x["distance"]),
                    "s",
                    ms=4,
                    color=line.get_color(),
                    mfc=line.get_color() if x["used"] == "1" else "none",
                )
            if mine[0]["limit_error"]:
                left.axhline(float(mine[0]["limit_error"]), color=line.get_color(), ls=":", lw=0.8)
    d_all = sorted({float(r["jump"]) for r in rows})
    for order, style in ((1, ":"), (2, "-.")):
        anchor = min(float(r["error"]) for r in rows if float(r["jump"]) == d_all[-1])
        left.loglog(d_all, [anchor * (d / d_all[-1]) ** order for d in d_all], "k" + style, lw=0.8, label="slope %d" % order)
    left.axhline(0.01, color="grey", lw=0.8)
    right.axhline(100, color="grey", lw=0.8)
    left.set_xlabel("jump D [s of slow time]")
    left.set_ylabel("final profile error (max |h - h_ref| / max h_ref)")
    right.set_xlabel("jump D [s of slow time]")
    right.set_ylabel("speed-up (reference CPU / multi-scale CPU)")
    for ax in (left, right):
        ax.grid(alpha=0.3, which="both")
        log_axes_plain(ax)
        legend(ax, fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return 0


def main(argv):
    if len(argv) < 5:
        sys.stderr.write(__doc__)
        return 2
    mode, data, png, title = argv[1:5]
    rows = list(csv.DictReader(open(data, newline="")))
    if not rows:
        sys.stderr.write("plot_wear.py: %s has no rows\n" % data)
        return 1
    if mode == "depth":
        reference = list(csv.DictReader(open(argv[5], newline=""))) if len(argv) > 5 else []
        depth_figure(rows, png, title, reference)
        return 0
    if mode == "profile":
        profile_figure(rows, png, title)
        return 0
    if mode == "jump":
        distances = list(csv.DictReader(open(argv[5], newline=""))) if len(argv) > 5 else []
        return jump_figure(rows, png, title, distances)
    sys.stderr.write(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
