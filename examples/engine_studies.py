#!/usr/bin/python3
"""The verification table of docs/engines.md: every integrator of the engine adapters
(examples/mujoco, examples/simbody) through `flexref converge --external`, one study per scene
and integrator, with the observed order of convergence of the attitude (metric rotation), the
body-frame angular velocity (angular_velocity) and the tracked points (points).

The attitude study runs the adapter once per level and keeps its files; the other two
quantities are measured on the same files with `converge --runs`, so every integrator runs
once per level. Writes OUT/<scene>/<engine>_<integrator>/<metric>/ (each a converge study)
and OUT/table.csv, OUT/table.md.

    examples/engine_studies.py [--out out/engines] [--jobs 1] [--scenes free_spin,...]
                               [--engines mujoco,simbody]

Run it with `nice` on a shared machine. Needs build/app/flexref and the adapters
(build/examples/mujoco/flexref_mujoco, build/examples/simbody/flexref_simbody).
"""
import argparse
import csv
import os
import re
import subprocess
import sys

FLEXREF = "build/app/flexref"
ADAPTERS = {
    "mujoco": "build/examples/mujoco/flexref_mujoco",
    "simbody": "build/examples/simbody/flexref_simbody",
}
# (integrator, the order its engine claims or is known for)
INTEGRATORS = {
    "mujoco": [("euler", 1), ("rk4", 4), ("implicit", 1)],
    "simbody": [("euler", 1), ("rk2", 2), ("rk3", 3), ("merson", 4), ("feldberg", 5),
                ("verlet", 3), ("semi-euler", 1), ("semi-euler2", 1)],
}
# scene: (coarsest step for claimed orders 1-2, for orders 3-5, levels, engines that map it).
# heavy_top spins at 150 rad/s: h|W| = 0.3 and 0.6 at its coarsest steps; the others start at
# h|W| <= 0.1. The higher orders start coarser on free_spin, whose 100 s put their finest
# levels at round-off (~3e-12) otherwise; the steps must divide the output step (0.01 s but
# for free_spin's 0.1 s) and book_toss's pulse (0.1 s).
SCENES = {
    "free_spin": (0.01, 0.04, 6, ("mujoco", "simbody")),
    "heavy_top": (0.002, 0.004, 6, ("mujoco", "simbody")),
    "book_toss": (0.01, 0.01, 6, ("mujoco", "simbody")),
    "pendulum": (0.01, 0.01, 6, ("mujoco", "simbody")),
    "bouncing_ball": (0.001, 0.001, 6, ("simbody",)),
}
METRICS = ("rotation", "angular_velocity", "points")


def observed(study_dir, label):
    """The observed order of a study as the table shows it: the least-squares order and the
    number of levels it was fitted from, or, when converge refused to fit one, the pairwise
    orders it has and the statuses of the other levels."""
    text = open(os.path.join(study_dir, "convergence.txt")).read()
    m = re.search(r"^\s*%s\s+claimed \S+, observed (\S+) over (\d+) levels" % re.escape(label),
                  text, re.M)
    if m and m.group(1) != "refused":
        return "%.2f (%s)" % (float(m.group(1)), m.group(2))
    pairwise, statuses = [], []
    with open(os.path.join(study_dir, "convergence.csv")) as f:
        for row in csv.DictReader(f):
            statuses.append(row["status"])
            if row["order"] != "nan" and row["status"] in ("ok", "round-off"):
                pairwise.append("%.2f" % float(row["order"]))
    return "- [%s; %s]" % (" ".join(pairwise), ", ".join(
        sorted(set(s.split(":")[0] for s in statuses))))


def run(cmd):
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return result.returncode, result.stdout


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out/engines")
    parser.add_argument("--jobs", default="1")
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--engines", default=",".join(ADAPTERS))
    parser.add_argument("--flexref", default=FLEXREF, help="the flexref program to run")
    parser.add_argument("--integrators", default="", help="only these (comma-separated)")
    parser.add_argument("--dt", type=float, default=0.0, help="the coarsest step (else the scene's)")
    parser.add_argument("--levels", type=int, default=0, help="levels (else the scene's)")
    args = parser.parse_args()
    rows = []
    for scene in args.scenes.split(","):
        dt_low, dt_high, scene_levels, engines = SCENES[scene]
        for engine in args.engines.split(","):
            if engine not in engines:
                continue
            for integrator, claimed in INTEGRATORS[engine]:
                if args.integrators and integrator not in args.integrators.split(","):
                    continue
                dt = args.dt or (dt_low if claimed <= 2 else dt_high)
                levels = args.levels or scene_levels
                label = "%s_%s" % (engine, integrator.replace("-", "_"))
                base = os.path.join(args.out, scene, label)
                command = "%s {scene} {dt} {output} --integrator %s" % (ADAPTERS[engine],
                                                                        integrator)
                row = {"scene": scene, "engine": engine, "integrator": integrator,
                       "claimed": claimed, "dt": dt, "levels": levels, "command": (
                           "%s converge scenes/%s.toml --external \"%s\" --label %s --order %d "
                           "--dt %g --levels %d --metric rotation --out %s"
                           % (FLEXREF, scene, command, label, claimed, dt, levels,
                              os.path.join(base, "rotation")))}
                code, text = run([args.flexref, "converge", "scenes/%s.toml" % scene, "--external",
                                  command, "--label", label, "--order", str(claimed), "--dt",
                                  str(dt), "--levels", str(levels), "--metric", "rotation",
                                  "--jobs", args.jobs, "--out", os.path.join(base, "rotation")])
                if not os.path.exists(os.path.join(base, "rotation", "convergence.txt")):
                    print("%s %s: converge failed (%d):\n%s" % (scene, label, code, text),
                          file=sys.stderr)
                    continue
                runs = []
                for level in range(levels):
                    runs.append("%.17g=%s" % (dt / 2 ** level, os.path.join(
                        base, "rotation", "run_%s_%d.csv" % (label, level))))
                for metric in METRICS:
                    study = os.path.join(base, metric)
                    if metric != "rotation":
                        run([args.flexref, "converge", "scenes/%s.toml" % scene, "--runs"] + runs +
                            ["--label", label, "--order", str(claimed), "--metric", metric,
                             "--jobs", args.jobs, "--out", study])
                    if not os.path.exists(os.path.join(study, "convergence.txt")):
                        row[metric] = "refused"
                        continue
                    row[metric] = observed(study, label)
                rows.append(row)
                print("%-14s %-20s claimed %d  rotation %-12s angular_velocity %-12s points %s"
                      % (scene, label, claimed, row["rotation"], row["angular_velocity"],
                         row["points"]), flush=True)
    os.makedirs(args.out, exist_ok=True)
    fields = ["scene", "engine", "integrator", "claimed", "dt", "levels"] + list(METRICS) + [
        "command"]
    with open(os.path.join(args.out, "table.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write("| scene | engine | integrator | claimed | attitude | angular velocity | "
                "points |\n|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write("| %s | %s | %s | %d | %s | %s | %s |\n" % (
                r["scene"], r["engine"], r["integrator"], r["claimed"], r["rotation"],
                r["angular_velocity"], r["points"]))


if __name__ == "__main__":
    main()
