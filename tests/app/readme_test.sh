#!/usr/bin/env bash
# The README as a newcomer meets it (issue 50): its first screen has a picture within 40 lines
# and a flexref command to paste within 60; the quickstart's commands run as written and print
# the figures the README shows; the self-check table's reference errors and the main job's
# closing lines are those the commands print. The commands and the figures are read from
# README.md itself (and the main job's command from scripts/main_job.sh), so the README and
# this test cannot diverge.
#
# The commands run from a folder of their own laid out as a checkout (build/app/flexref the
# built binary, scenes/ the repository's), so that their outputs land there. How the README is
# read: in "## Quickstart", each ```sh block is one command (lines ending in \ continue it) and
# the ```text block after it what it prints: every line of that block must be a line of the
# command's standard output, in order (lines may be left out between them), where "…" stands for
# any text (CPU times, paths, a line cut short); a figure that drifts is a line that no longer
# matches. Every command must exit 0.
# Usage: readme_test.sh /path/to/flexref (from the repository root).
set -uo pipefail
flexref=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/build/app"
ln -s "$(cd "$(dirname "$flexref")" && pwd)/$(basename "$flexref")" "$tmp/build/app/flexref"
ln -s "$PWD/scenes" "$tmp/scenes"
FLEXREF_PROGRESS=off /usr/bin/python3 - README.md scripts/main_job.sh "$tmp" <<'EOF'
import re
import subprocess
import sys

readme_path, main_job_path, folder = sys.argv[1:4]
lines = open(readme_path, encoding="utf-8").read().split("\n")
failures = []


def fail(message):
    failures.append(message)
    print("FAIL: " + message)


def section(title):
    """The lines of the README section "## title" (up to the next "## "), with their numbers."""
    start = next((i for i, l in enumerate(lines) if l.strip() == "## " + title), None)
    if start is None:
        fail(f"README has no section '## {title}'")
        return []
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")),
               len(lines))
    return [(i + 1, lines[i]) for i in range(start + 1, end)]


def blocks(numbered):
    """The fenced blocks of numbered lines: (language, first line number, [lines])."""
    out, current = [], None
    for number, line in numbered:
        if line.startswith("```"):
            if current is None:
                current = (line[3:].strip(), number + 1, [])
            else:
                out.append(current)
                current = None
        elif current is not None:
            current[2].append(line)
    return out


def commands(block_lines):
    """The commands of a shell block: lines ending in a backslash continue the next."""
    out, pending = [], ""
    for line in block_lines:
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        if (pending + line).strip():
            out.append((pending + line).strip())
        pending = ""
    return out


def run(command):
    """Runs a command as written in the checkout-like folder: (exit code, standard output)."""
    try:
        done = subprocess.run(command, shell=True, cwd=folder, capture_output=True, text=True,
                              timeout=300)
    except subprocess.TimeoutExpired:
        return -1, "", "timed out after 300 s"
    return done.returncode, done.stdout, done.stderr


def pattern(expected):
    """A README output line as a regular expression: "…" is any text (a space before it is
    part of the elision: "(h = …) …" cuts a line short), the rest literal."""
    parts = expected.split("…")
    parts = [p.rstrip() if k + 1 < len(parts) else p for k, p in enumerate(parts)]
    return re.compile("^" + ".*".join(re.escape(p) for p in parts) + "$")


def check_output(where, command, expected, stdout):
    """Every expected line is a line of stdout, in order."""
    actual = stdout.split("\n")
    k = 0
    for offset, line in enumerate(expected):
        if not line.strip() or line.strip() == "…":
            continue
        p = pattern(line)
        while k < len(actual) and not p.match(actual[k]):
            k += 1
        if k == len(actual):
            fail(f"README.md:{where + offset}: '{line}' is not in the output of `{command}` "
                 f"(in order), which printed:\n{stdout}")
            return
        k += 1


# The first screen: a picture within the first 40 lines (a file of the repository), a flexref
# command to paste within the first 60 (a line of a shell block that starts with the binary).
image = next((i for i, l in enumerate(lines[:40]) if re.match(r"!\[[^]]*\]\([^)]+\)", l)), None)
if image is None:
    fail("no image in the README's first 40 lines")
else:
    path = re.match(r"!\[[^]]*\]\(([^)]+)\)", lines[image]).group(1)
    try:
        open(path, "rb").close()
    except OSError:
        fail(f"README.md:{image + 1}: the image {path} is not a file of the repository")
first = next((number + offset for lang, number, body in blocks(list(enumerate(lines, 1)))
              if lang == "sh" for offset, l in enumerate(body)
              if l.startswith("build/app/flexref ")), None)
if first is None or first > 60:
    fail(f"the first flexref command to paste is at line {first}, not within the first 60")

# The quickstart: five commands, each followed by what it prints.
quick = blocks(section("Quickstart"))
steps = []
for k, (lang, number, body) in enumerate(quick):
    if lang != "sh":
        continue
    cmds = commands(body)
    if len(cmds) != 1 or k + 1 == len(quick) or quick[k + 1][0] != "text":
        fail(f"README.md:{number}: a quickstart block is one command followed by a ```text "
             f"block of what it prints")
        continue
    steps.append((cmds[0], quick[k + 1][1], quick[k + 1][2]))
if len(steps) != 5:
    fail(f"the quickstart has {len(steps)} commands, not five")
for command, where, expected in steps:
    code, stdout, stderr = run(command)
    if code != 0:
        fail(f"`{command}` failed (exit {code}): {stderr}{stdout}")
        continue
    check_output(where, command, expected, stdout)

# The self-check table: each scene's reference error is what the README's command prints.
checks = section("What flexref checks itself against")
text = " ".join(l for _, l in checks)
template = re.search(r"`(build/app/flexref reference scenes/SCENE\.toml[^`]*)`", text)
rows = [(n, l) for n, l in checks if re.match(r"\| `[a-z0-9_]+` \|", l)]
if template is None or not rows:
    fail("the self-check section has no command template or no scene rows")
else:
    for number, row in rows:
        scene = re.match(r"\| `([a-z0-9_]+)` \|", row).group(1)
        figure = re.search(r"([0-9.]+e[-+][0-9]+)", row.rstrip(" |").split("|")[-1]).group(1)
        command = template.group(1).replace("SCENE", scene)
        code, stdout, stderr = run(command)
        if code != 0:
            fail(f"`{command}` failed (exit {code}): {stderr}")
            continue
        printed = re.search(r"^estimated error \([^)]*\): ([0-9.e+-]+) ", stdout, re.M)
        if printed is None or printed.group(1) != figure:
            fail(f"README.md:{number}: {scene}'s reference error {figure} is not what "
                 f"`{command}` prints: {printed.group(1) if printed else stdout}")

# The main job's closing lines: its command is the last flexref command of scripts/main_job.sh.
job = commands(open(main_job_path, encoding="utf-8").read().split("\n"))
job = [c for c in job if c.startswith("./build/app/flexref ")]
two = blocks(section("Two commands (fresh Debian 12)"))
ends = [b for b in two if any(l.startswith("observed order") for l in b[2])]
if not job or not ends:
    fail("no main-job command in scripts/main_job.sh or no closing lines in the README")
else:
    code, stdout, stderr = run(job[-1])
    if code != 0:
        fail(f"the main job `{job[-1]}` failed (exit {code}): {stderr}")
    else:
        check_output(ends[0][1], job[-1], ends[0][2], stdout)

print(f"readme: {'%d failed' % len(failures) if failures else 'all checks passed'}")
sys.exit(1 if failures else 0)
EOF
