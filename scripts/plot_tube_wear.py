#!/usr/bin/python3
"""Figure of docs/contact_results.md, "Tube in a support with clearance": the reference wear work
of scenes/tube_support_impact.toml at the support (with its impacts) and the schemes' relative
wear-work error against the step, from the files `flexref converge --metric wear` writes.

    flexref converge scenes/tube_support_impact.toml --model lte --metric wear --schemes c2 \
        --dt 1e-4 --levels 5 --reference-solver cvode --reference-rtol 1e-11 --out conv10
    scripts/plot_tube_wear.py conv10 docs/gallery/tube_support_impact_wear.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(folder, output):
    rows = list(csv.DictReader(open(f"{folder}/reference.csv")))
    t = [float(r["t"]) for r in rows]
    wear = [float(r["support.wear_work"]) for r in rows]
    impacts = [float(r["support.impacts"]) for r in rows]
    levels = [r for r in csv.DictReader(open(f"{folder}/convergence.csv")) if r["status"] == "ok"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    a.plot(t, wear, color="C0")
    a.set_xlabel("t [s]")
    a.set_ylabel("support.wear_work [J]", color="C0")
    a2 = a.twinx()
    a2.plot(t, impacts, color="C1", lw=0.8)
    a2.set_ylabel("support.impacts", color="C1")
    a.set_title("reference (CVODE rtol 1e-11, est. rel. error 7.6e-8)")
    for scheme in sorted({r["scheme"] for r in levels}):
        pts = [(float(r["h"]), float(r["error"])) for r in levels if r["scheme"] == scheme]
        b.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=scheme)
    hs = [float(r["h"]) for r in levels]
    b.loglog(hs, [1e-2 * (h / max(hs)) ** 2 for h in hs], "k:", label="slope 2")
    b.axhline(1e-2, color="gray", lw=0.8)
    b.set_xlabel("step h [s]")
    b.set_ylabel("relative error of the final wear work")
    b.set_title("schemes (LTE, 10 s): 1 % at h = 2.5e-5 s")
    b.legend()
    fig.tight_layout()
    fig.savefig(output, dpi=120)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
