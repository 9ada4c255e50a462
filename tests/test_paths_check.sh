#!/usr/bin/env bash
# Tests write only inside a folder of their own, unique per process and removed afterwards:
# C++ tests through tests/support/temp_dir.hpp (TempDir, made by mkdtemp), shell tests through
# `mktemp -d` with a trap that removes it. A fixed name in the shared temporary folder collides
# when two suites run at once (two builds, or ctest -j), a file left behind changes
# the next run's verdict, and a path outside the test's folder touches the machine. This check
# reads what the tests write (comments and, in shell scripts, here-documents aside) and fails on:
#  C++ (tests/support/temp_dir.* aside):
#  - naming the temporary folder or making temporary names: temp_directory_path, "/tmp, TMPDIR,
#    P_tmpdir, tmpnam, mkstemp, mkdtemp, a name from the process id;
#  - a literal path where a process could write: under /tmp, /var, /dev (but /dev/null and the
#    program's own descriptors /dev/fd/N), /home, /root, /run, /proc (but /proc/self/fd), ~/;
#  - a file or folder written, made or removed at a literal path (ofstream, fopen, write_csv,
#    write_output_file, create_directory, remove…) rather than under the test's TempDir;
#  shell tests:
#  - `mktemp` without a trap that removes the folder;
#  - the shared temporary folder (/tmp, $TMPDIR, /var/tmp, /dev/shm) named other than to list
#    it with `ls` (a check that nothing was left behind), and a listing of /tmp that ignores
#    $TMPDIR, where the programs make their temporary folders (`ls "${TMPDIR:-/tmp}"`);
#  - a /dev path other than /dev/null, /dev/stdout, /dev/stderr and /dev/fd/N;
#  - an output (a redirection, -o, --out, --output) to a path that is not under a variable (the
#    test's folder): a literal path, absolute or relative.
# Usage: test_paths_check.sh TESTS_DIR
set -euo pipefail
tests=$1
command -v python3 >/dev/null || { echo "FAIL: test_paths_check.sh needs python3"; exit 1; }
python3 - "$tests" "$(basename "$0")" <<'PYTHON'
import os
import re
import sys

root, self_name = sys.argv[1], sys.argv[2]
failures = []


def fail(path, k, line, why):
    failures.append(f'{path}:{k + 1}: {line.strip()} ({why})')


def split_comment(line, marker):
    """The line's code before its comment: `//` (C++) or `#` (shell, at a word's start) outside
    string literals; in C++ a '…' is a character literal, in shell a string."""
    i = 0
    while i < len(line):
        c = line[i]
        if c in '"\'':
            j = i + 1
            while j < len(line) and line[j] != c:
                j += 2 if line[j] == '\\' and c == '"' or (line[j] == '\\' and marker == '//') else 1
            i = j + 1
            continue
        if line.startswith(marker, i) and (marker == '//' or i == 0 or line[i - 1] in ' \t;'):
            return line[:i]
        i += 1
    return line


# --- C++ ---------------------------------------------------------------------------------------
TEMPORARY = re.compile(r'temp_directory_path|"/tmp|\bTMPDIR\b|P_tmpdir|tmpnam|mkstemp|mkdtemp|'
                       r'to_string\((?:::)?getpid')
WRITABLE_LITERAL = re.compile(r'"(?:/tmp|/var/|/dev/(?!null"|fd/)|/home/|/root|/run/|'
                              r'/proc/(?!self/fd/)|~/)')
OWN_DESCRIPTOR = r'(?!/dev/fd/|/proc/self/fd/)'
LITERAL_WRITE = re.compile(r'(?:\b(?:ofstream|fopen|open|write_output_file|create_director(?:y|ies)|'
                           r'remove|remove_all|rename|copy_file)\s*\(\s*|'
                           r'\bwrite_csv\s*\([^,()]*,\s*|\bofstream\s+\w+\s*\(\s*)"' +
                           OWN_DESCRIPTOR)
for directory, _, names in os.walk(root):
    for name in sorted(names):
        path = os.path.join(directory, name)
        if not name.endswith(('.cpp', '.hpp')) or re.search(r'/support/temp_dir\.(cpp|hpp)$', path):
            continue
        with open(path, encoding='utf-8') as f:
            for k, line in enumerate(f.read().split('\n')):
                code = split_comment(line, '//')
                if TEMPORARY.search(code):
                    fail(path, k, line, 'write into a testing::TempDir, tests/support/temp_dir.hpp')
                elif WRITABLE_LITERAL.search(code):
                    fail(path, k, line, 'a path outside the test\'s TempDir')
                elif LITERAL_WRITE.search(code):
                    fail(path, k, line, 'written at a literal path: write under the test\'s TempDir')

# --- shell -------------------------------------------------------------------------------------
SHARED = re.compile(r'/tmp\b|\bTMPDIR\b|/var/tmp|/dev/shm')
DEVICE = re.compile(r'/dev/(?!null\b|stdout\b|stderr\b|fd/)\w')
HEREDOC = re.compile(r"<<-?\s*(['\"]?)(\w+)\1")


def unquoted(code):
    """The code with double-quoted strings as V (starting with $: a variable's path) or Q, and
    single-quoted ones as Q."""
    code = re.sub(r'"\$[^"]*"', 'V', code)
    code = re.sub(r'"[^"]*"', 'Q', code)
    return re.sub(r"'[^']*'", 'Q', code)


for directory, _, names in os.walk(root):
    for name in sorted(names):
        path = os.path.join(directory, name)
        # This check, and the test of the checks, which holds every refused form as its data.
        if not name.endswith('.sh') or name in (self_name, 'check_scripts_test.sh'):
            continue
        with open(path, encoding='utf-8') as f:
            lines = f.read().split('\n')
        if any('mktemp' in split_comment(l, '#') for l in lines) and not any(
                re.match(r"""^trap 'rm -rf "\$[a-z_]+"' EXIT""", l) for l in lines):
            failures.append(f'{path} makes a temporary folder without a trap that removes it')
        heredoc_end = None
        for k, line in enumerate(lines):
            if heredoc_end is not None:
                if line.strip() == heredoc_end:
                    heredoc_end = None
                continue
            code = split_comment(line, '#')
            h = HEREDOC.search(code)
            if h:
                heredoc_end = h.group(2)
            if SHARED.search(code) and not re.match(r'\s*ls\b', code):
                fail(path, k, line, 'names the shared temporary folder: use the mktemp -d folder')
            elif re.match(r'\s*ls\b.*/tmp\b', code) and 'TMPDIR' not in code:
                fail(path, k, line, 'lists /tmp where the programs use $TMPDIR: ${TMPDIR:-/tmp}')
            if DEVICE.search(code):
                fail(path, k, line, 'a device path')
            plain = unquoted(code)
            for target in re.findall(r'(?<![<>&-])[0-9&]?>>?\s*([^\s&>;|)]+)', plain):
                if target not in ('V', '/dev/null', '/dev/stdout', '/dev/stderr') and \
                        not target.startswith('$') and re.search(r'[A-Za-z]', target) and \
                        ('/' in target or '.' in target or target == 'Q'):
                    fail(path, k, line, 'writes outside the test\'s folder')
            for command in re.split(r'[|;]|&&|(?<!\\)\(', plain):
                if re.match(r'\s*(?:grep|egrep|zgrep|find)\b', command):
                    continue  # grep -o: the matching part; find -o: or
                for target in re.findall(r'(?:^|\s)(?:-o|--out|--output)(?:=|\s+)([^\s)]+)',
                                         command):
                    if target not in ('V', '-') and not target.startswith('$'):
                        fail(path, k, line, 'an output outside the test\'s folder')

for f in failures:
    print('FAIL: ' + f)
sys.exit(1 if failures else 0)
PYTHON
