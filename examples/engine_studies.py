#!/usr/bin/python3
"""The verification table of docs/engines.md: every integrator of the engine adapters
(examples/mujoco, examples/simbody) through `flexref converge --external`, one study per scene
and integrator, with the observed order of convergence of the attitude (metric rotation), the
body-frame angular velocity (angular_velocity) and the tracked points (points).

The attitude study runs the adapter once per level and keeps its files; the other two
quantities are measured on the same files with `converge --runs`, so every integrator runs
once per level. Writes OUT/<scene>/<engine>_<integrator>/<metric>/ (each a converge study)
and OUT/table.csv, OUT/table.md.

With --work-precision, `flexref work-precision` instead, per scene and integrator beside
flexref's schemes C1, C2 and NMB (metric rotation+points, CPU time the minimum of --repeats
runs; the adapters report their integration's CPU time alone, as flexref times its schemes):
OUT/<scene>/<label>/ and OUT/work_precision.md, the cheapest CPU time of each method reaching
each target error.

    examples/engine_studies.py [--out out/engines] [--jobs 1] [--scenes free_spin,...]
                               [--scene-dir scenes]
                               [--engines mujoco,simbody] [--integrators rk4,...]
                               [--dt H --levels N] [--work-precision [--repeats 3]]
                               [--jointed] [--adapter-options "--solref 0.02 1"]

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
# heavy_top spins at 150 rad/s: h|W| = 0.3 and 0.375 at its coarsest steps; the others start at
# h|W| <= 0.1. The higher orders start coarser on free_spin, whose 100 s put their finest
# levels at round-off (~3e-12) otherwise; the steps must divide the output step (0.01 s but
# for free_spin's 0.1 s) and book_toss's pulse (0.1 s).
SCENES = {
    "free_spin": (0.01, 0.05, 6, ("mujoco", "simbody")),
    "heavy_top": (0.002, 0.0025, 6, ("mujoco", "simbody")),
    "book_toss": (0.01, 0.01, 6, ("mujoco", "simbody")),
    "pendulum": (0.01, 0.01, 6, ("mujoco", "simbody")),
    "bouncing_ball": (0.001, 0.001, 6, ("simbody",)),
    # The jointed benchmarks (--jointed): steps dividing their output steps (1e-3 s; Andrews'
    # 1e-4 s), coarsest where the engines' explicit methods still run (Andrews' squeezer turns
    # K1 at up to 1.5e3 rad/s). MuJoCo cannot drive the slider-crank's crank and refuses it.
    "heavy_top_spherical": (0.002, 0.0025, 6, ("mujoco", "simbody")),
    "double_pendulum_ideal": (0.001, 0.001, 6, ("mujoco", "simbody")),
    "four_bar": (0.001, 0.001, 6, ("mujoco", "simbody")),
    "andrews_squeezer": (2e-5, 2e-5, 6, ("mujoco", "simbody")),
    "slider_crank": (0.001, 0.001, 6, ("simbody",)),
}
JOINTED = ("heavy_top_spherical", "double_pendulum_ideal", "four_bar", "andrews_squeezer",
           "slider_crank")
METRICS = ("rotation", "angular_velocity", "points")


# The metric of docs/engines.md's work-precision and jointed tables: they were measured in
# rotation+points (rad + m) before the default became the dimensionless 'relative'
# (docs/decisions.md, "The default metric"); named here so that a rerun reproduces them.
TABLE_METRIC = "rotation+points"

def observed(study_dir, label):
    """The observed order of a study as the table shows it: the least-squares order and the
    number of levels it was fitted from (or "-" when converge refused to fit one), then the
    pairwise order of the two finest levels that are ok (not round-off, uncertified, failed
    or left out)."""
    text = open(os.path.join(study_dir, "convergence.txt")).read()
    m = re.search(r"^\s*%s\s+claimed \S+, observed (\S+) over (\d+) levels" % re.escape(label),
                  text, re.M)
    fit = "%.2f (%s)" % (float(m.group(1)), m.group(2)) if m and m.group(1) != "refused" else "-"
    last = None
    with open(os.path.join(study_dir, "convergence.csv")) as f:
        rows = list(csv.DictReader(f))
    for previous, row in zip(rows, rows[1:]):
        if row["status"] == "ok" and previous["status"] == "ok":
            last = float(row["order"])
    return fit + ("; %.2f" % last if last is not None else "")


def run(cmd):
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return result.returncode, result.stdout


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out/engines")
    parser.add_argument("--jobs", default="1")
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--scene-dir", default="scenes",
                        help="where SCENE.toml is read (a folder of shortened copies, say)")
    parser.add_argument("--engines", default=",".join(ADAPTERS))
    parser.add_argument("--flexref", default=FLEXREF, help="the flexref program to run")
    parser.add_argument("--integrators", default="", help="only these (comma-separated)")
    parser.add_argument("--dt", type=float, default=0.0, help="the coarsest step (else the scene's)")
    parser.add_argument("--levels", type=int, default=0, help="levels (else the scene's)")
    parser.add_argument("--reuse", action="store_true",
                        help="tabulate the studies already in OUT instead of running them again")
    parser.add_argument("--work-precision", action="store_true")
    parser.add_argument("--jointed", action="store_true",
                        help="the jointed benchmarks: one rotation+points study per scene and "
                             "integrator with each level's joint violation (OUT/jointed.md)")
    parser.add_argument("--adapter-options", default="",
                        help="appended to every adapter command (--solref 0.02 1, say)")
    parser.add_argument("--repeats", default="3")
    parser.add_argument("--schemes", default="c1,c2,nmb",
                        help="flexref's schemes beside the engines in --work-precision "
                             "(genalpha on scenes with ideal joints, which the others refuse)")
    parser.add_argument("--solvers", default="cvode",
                        help="flexref's reference solvers beside them in --work-precision")
    args = parser.parse_args()
    if args.work_precision:
        return work_precision(args)
    if args.jointed:
        return jointed(args)
    rows = []
    for scene in args.scenes.split(","):
        scene_file = os.path.join(args.scene_dir, scene + ".toml")
        for engine, integrator, claimed, dt, levels, label, command in methods(args, scene):
            base = os.path.join(args.out, scene, label)
            row = {"scene": scene, "engine": engine, "integrator": integrator,
                   "claimed": claimed, "dt": dt, "levels": levels, "command": (
                       "%s converge %s --external \"%s\" --label %s --order %d "
                       "--dt %g --levels %d --metric rotation --out %s"
                       % (FLEXREF, scene_file, command, label, claimed, dt, levels,
                          os.path.join(base, "rotation")))}
            done = args.reuse and os.path.exists(
                os.path.join(base, "rotation", "convergence.txt"))
            code, text = (0, "") if done else run([
                              args.flexref, "converge", scene_file, "--external",
                              command, "--label", label, "--order", str(claimed), "--dt",
                              str(dt), "--levels", str(levels), "--metric", "rotation",
                              "--jobs", args.jobs, "--out", os.path.join(base, "rotation")])
            if not os.path.exists(os.path.join(base, "rotation", "convergence.txt")):
                print("%s %s: converge failed (%d):\n%s" % (scene, label, code, text),
                      file=sys.stderr)
                continue
            # The levels whose run wrote its file: a level that failed (the engine went
            # unstable at the coarse steps) has none, and converge --runs refuses a missing
            # file before any work.
            runs = []
            for level in range(levels):
                path = os.path.join(base, "rotation", "run_%s_%d.csv" % (label, level))
                if os.path.exists(path):
                    runs.append("%.17g=%s" % (dt / 2 ** level, path))
            for metric in METRICS:
                study = os.path.join(base, metric)
                if metric != "rotation" and not (
                        args.reuse and os.path.exists(os.path.join(study, "convergence.txt"))):
                    run([args.flexref, "converge", scene_file, "--runs"] + runs +
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


TARGETS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8)


def cheapest(runs, target):
    """The smallest CPU time of the runs (dicts of work_precision.csv) reaching `target`."""
    ok = [float(r["cpu_seconds"]) for r in runs
          if r["status"] == "ok" and float(r["error"]) <= target]
    return min(ok) if ok else None


def methods(args, scene):
    """The engine integrators to study on `scene` with their levels: (engine, integrator,
    claimed order, coarsest step, levels, label, the adapter's command template)."""
    dt_low, dt_high, scene_levels, engines = SCENES[scene]
    for engine in args.engines.split(","):
        if engine not in engines:
            continue
        for integrator, claimed in INTEGRATORS[engine]:
            if args.integrators and integrator not in args.integrators.split(","):
                continue
            yield (engine, integrator, claimed,
                   args.dt or (dt_low if claimed <= 2 else dt_high),
                   args.levels or scene_levels,
                   "%s_%s" % (engine, integrator.replace("-", "_")),
                   ("%s {scene} {dt} {output} --integrator %s %s" % (
                       ADAPTERS[engine], integrator, args.adapter_options)).strip())


def work_precision(args):
    """work-precision per scene and integrator; the table of cheapest CPU times."""
    lines = []
    for scene in args.scenes.split(","):
        if scene == "bouncing_ball":
            continue
        dt_low, dt_high, scene_levels, _ = SCENES[scene]
        runs_of = {}  # label -> its runs
        for engine, integrator, claimed, dt, levels, label, command in methods(args, scene):
            study = os.path.join(args.out, scene, label)
            code, text = run([args.flexref, "work-precision",
                              os.path.join(args.scene_dir, scene + ".toml"),
                              "--external", command, "--label", label, "--schemes",
                              args.schemes, "--solvers", args.solvers, "--tolerances",
                              "1e-6,1e-9", "--dt", str(dt), "--levels", str(levels),
                              "--repeats", args.repeats, "--metric", TABLE_METRIC,
                              "--jobs", args.jobs, "--out", study])
            table = os.path.join(study, "work_precision.csv")
            if not os.path.exists(table):
                print("%s %s: work-precision failed (%d):\n%s" % (scene, label, code, text),
                      file=sys.stderr)
                continue
            with open(table) as f:
                rows = list(csv.DictReader(f))
            # The schemes and the solver as the first study ran them (each study reruns them
            # at its own steps: those of the first one are kept).
            known = set(runs_of)
            for r in rows:
                if r["method"] not in known:
                    runs_of.setdefault(r["method"], []).append(r)
            print("%s %s: done" % (scene, label), flush=True)
        lines.append("\n%s (dt %g/%g, %d levels): cheapest CPU time [s] to reach the error "
                     "(rotation+points)\n" % (scene, dt_low, dt_high, scene_levels))
        lines.append("| method | " + " | ".join("%g" % t for t in TARGETS) + " |")
        lines.append("|---|" + "---|" * len(TARGETS))
        for method, runs in runs_of.items():
            cells = []
            for t in TARGETS:
                c = cheapest(runs, t)
                cells.append("%.2e" % c if c is not None else "-")
            lines.append("| %s | %s |" % (method, " | ".join(cells)))
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "work_precision.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def level_rows(study_dir, label):
    """The levels of one method in a converge study: (h, error, violation, status) from its
    convergence.txt table (the violation column is there for scenes with ideal joints)."""
    rows = []
    for line in open(os.path.join(study_dir, "convergence.txt")):
        cells = line.split()
        if len(cells) >= 8 and cells[0] == label and re.match(r"^[0-9.e+-]+$", cells[1]):
            rows.append((float(cells[1]), float(cells[3]), cells[6], " ".join(cells[7:])))
    return rows


def jointed(args):
    """One `converge --external` per jointed scene and integrator (metric rotation+points):
    the observed order, the levels off their joints, the finest level's error and joint
    violation; OUT/jointed.md and OUT/jointed.csv with each study's command."""
    rows = []
    scenes = args.scenes if args.scenes != ",".join(SCENES) else ",".join(JOINTED)
    for scene in scenes.split(","):
        scene_file = os.path.join(args.scene_dir, scene + ".toml")
        for engine, integrator, claimed, dt, levels, label, command in methods(args, scene):
            study = os.path.join(args.out, scene, label)
            cmd = [args.flexref, "converge", scene_file, "--external", command, "--label",
                   label, "--order", str(claimed), "--dt", "%g" % dt, "--levels",
                   str(levels), "--reference-solver", "cvode", "--metric", TABLE_METRIC,
                   "--jobs", args.jobs, "--out", study]
            if not (args.reuse and os.path.exists(os.path.join(study, "convergence.txt"))):
                code, text = run(cmd)
            if not os.path.exists(os.path.join(study, "convergence.txt")):
                print("%s %s: converge failed:\n%s" % (scene, label, text), file=sys.stderr)
                continue
            fit = observed(study, label)
            levels_of = level_rows(study, label)
            off = sum(1 for r in levels_of if r[3] == "off-joints")
            finest = next((r for r in reversed(levels_of) if not r[3].startswith("failed")),
                          None)
            row = {"scene": scene, "engine": engine, "integrator": integrator,
                   "claimed": claimed, "order": fit, "off_joints": off,
                   "levels": len(levels_of),
                   "finest_h": "%.3g" % finest[0] if finest else "-",
                   "finest_error": "%.3g" % finest[1] if finest else "-",
                   "finest_violation": finest[2] if finest else "-",
                   "statuses": ",".join(r[3].replace(" ", "_") for r in levels_of),
                   "command": " ".join(c if " " not in c else '"%s"' % c for c in cmd)}
            rows.append(row)
            print("%-22s %-20s order %-14s off-joints %d/%d  finest h %s error %s violation %s"
                  % (scene, label, fit, off, len(levels_of), row["finest_h"],
                     row["finest_error"], row["finest_violation"]), flush=True)
    os.makedirs(args.out, exist_ok=True)
    fields = ["scene", "engine", "integrator", "claimed", "order", "off_joints", "levels",
              "finest_h", "finest_error", "finest_violation", "statuses", "command"]
    with open(os.path.join(args.out, "jointed.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    with open(os.path.join(args.out, "jointed.md"), "w") as f:
        f.write("| scene | integrator | claimed | observed | off-joints | finest h | error | "
                "violation |\n|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write("| %s | %s %s | %d | %s | %d of %d | %s | %s | %s |\n" % (
                r["scene"], r["engine"], r["integrator"], r["claimed"], r["order"],
                r["off_joints"], r["levels"], r["finest_h"], r["finest_error"],
                r["finest_violation"]))


if __name__ == "__main__":
    main()
