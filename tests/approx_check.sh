#!/usr/bin/env bash
# Every tolerance in a test is explicit and derived (docs/design/style.md, "Tests": "every
# tolerance has a comment that derives it"). This check reads the C++ tests' CHECK and REQUIRE
# statements and fails on:
#  - a silent default tolerance: a Catch2 Approx(x) without .epsilon(…) or .margin(…) (Catch2's
#    relative 1.2e-5, float's epsilon × 100), an Eigen a.isApprox(b) without its precision
#    argument (Eigen's 1e-12);
#  - a tolerance no comment derives: a statement that compares with a tolerance — an Approx, an
#    isApprox, or a `<`/`<=` comparison of an abs(…), a norm(), a maxCoeff() or a literal in
#    exponent form (`std::abs(a - b) < 1e-12`, `error <= 1e3 * rtol`) — with no comment on its
#    lines, none on the lines directly above it (up to a blank line, or the enclosing
#    definition and the comment just above that), none in the enclosing definition that writes
#    its literal (`1e-12`), and, when the tolerance is a named value (`<= tolerance`,
#    `.margin(bound)`), none so placed at a line that defines that name.
# Comments are the derivation's place; where a tolerance's reason is elsewhere (a helper's
# header, the test case's first lines) a comment says where. Exact comparisons (==) are not
# tolerances and are not read.
# Usage: approx_check.sh TESTS_DIR
set -euo pipefail
tests=$1
command -v python3 >/dev/null || { echo "FAIL: approx_check.sh needs python3"; exit 1; }
python3 - "$tests" <<'PYTHON'
import os
import re
import sys

root = sys.argv[1]
STATEMENT = re.compile(r'\b(?:CHECK|REQUIRE|CHECK_FALSE|REQUIRE_FALSE)\s*\(')
TEMPLATE_ARGUMENTS = re.compile(r'(?<=\w)<[\w:, ]*>')
EXPONENT_LITERAL = re.compile(r'(?<![\w.])\d+(?:\.\d*)?[eE][-+]?\d+')
DIFFERENCE = re.compile(r'\b(?:abs|fabs)\s*\(|\.norm\(\)|\.maxCoeff\(\)')
CATCH_APPROX = re.compile(r'(?<![\w:])(?:Catch::)?Approx\s*\(')
EIGEN_APPROX = re.compile(r'\.isApprox\s*\(')


def split_comment(line):
    """(code, comment) of a line: the comment starts at a // outside string and character
    literals."""
    quote = None
    i = 0
    while i < len(line):
        c = line[i]
        if quote:
            if c == '\\':
                i += 1
            elif c == quote:
                quote = None
        elif c in '"\'':
            quote = c
        elif line.startswith('//', i):
            return line[:i], line[i:]
        i += 1
    return line, ''


def code_of(line):
    return split_comment(line)[0]


def comment_of(line):
    return split_comment(line)[1]


def derived_above(lines, k):
    """A comment on line k or on the lines directly above it, up to a blank line, or up to the
    enclosing definition (a line at column 0) and the comment just above that."""
    if comment_of(lines[k]):
        return True
    j = k - 1
    while j >= 0:
        line = lines[j]
        if line.strip() == '':
            return False
        if comment_of(line):
            return True
        if not line[0].isspace():
            return j > 0 and lines[j - 1].lstrip().startswith('//')
        j -= 1
    return False


def mentioned_in_scope(lines, k, literals):
    """A comment in the enclosing definition (from the last line at column 0 before k) up to
    line k that writes one of the literals."""
    j = k
    while j > 0 and not (lines[j] and not lines[j][0].isspace() and
                         not lines[j].startswith(('//', '#', '}'))):
        j -= 1
    return any(lit in comment_of(line) for line in lines[j:k + 1] for lit in literals)


def closing_parenthesis(text, open_index):
    """Index just past the parenthesis that closes the one at open_index, or -1."""
    depth = 0
    for i in range(open_index, len(text)):
        if text[i] == '(':
            depth += 1
        elif text[i] == ')':
            depth -= 1
            if depth == 0:
                return i + 1
    return -1


files = {}
for directory, _, names in os.walk(root):
    for name in names:
        if name.endswith(('.cpp', '.hpp')):
            path = os.path.join(directory, name)
            with open(path, encoding='utf-8') as f:
                files[path] = f.read().split('\n')

definitions = {}


def definition_sites(identifier):
    """Lines of the tests (any file) that define `identifier` (name = …, name{…}, name(…) …)."""
    if identifier not in definitions:
        pattern = re.compile(r'(?:^|[^\w.>])' + identifier + r'\s*(?:=(?!=)|\{|\()')
        definitions[identifier] = [
            (path, k) for path, lines in files.items() for k, line in enumerate(lines)
            if pattern.search(code_of(line)) and not STATEMENT.search(code_of(line))]
    return definitions[identifier]


failures = []
for path in sorted(files):
    lines = files[path]
    k = 0
    while k < len(lines):
        code = code_of(lines[k])
        m = STATEMENT.search(code)
        if not m:
            k += 1
            continue
        end = k  # the statement runs to its closing parenthesis (at most 15 lines)
        text = code[m.start():]
        while text.count('(') > text.count(')') and end - k < 15 and end + 1 < len(lines):
            end += 1
            text += '\n' + code_of(lines[end])
        flat = TEMPLATE_ARGUMENTS.sub('', text).replace('<<', '').replace('->', '')
        where = f'{path}:{k + 1}: {lines[k].strip()}'
        for a in CATCH_APPROX.finditer(text):
            close = closing_parenthesis(text, text.index('(', a.start()))
            if close < 0 or not re.match(r'\s*\.(epsilon|margin)\s*\(', text[close:]):
                failures.append(where + ' (a bare Approx: give it .epsilon(…) or .margin(…) '
                                'and the comment that derives it)')
        for a in EIGEN_APPROX.finditer(text):
            close = closing_parenthesis(text, a.end() - 1)
            depth = commas = 0
            for c in text[a.end():close - 1] if close > 0 else '':
                depth += c in '([{'
                depth -= c in ')]}'
                commas += c == ',' and depth == 0
            if commas == 0:
                failures.append(where + " (isApprox without its precision: Eigen's silent 1e-12; "
                                'give it and the comment that derives it)')
        tolerance = (CATCH_APPROX.search(text) or EIGEN_APPROX.search(text) or
                     ('<' in flat and (DIFFERENCE.search(flat) or EXPONENT_LITERAL.search(flat))))
        if tolerance:
            literals = [x.group(0) for x in EXPONENT_LITERAL.finditer(flat)]
            derived = (any(derived_above(lines, j) for j in range(k, end + 1)) or
                       (literals and mentioned_in_scope(lines, k, literals)))
            if not derived:
                named = re.findall(r'(?:<=?|epsilon\(|margin\()\s*([A-Za-z_]\w*)', flat)
                named += re.findall(r'isApprox\(.*,\s*([A-Za-z_]\w*)', flat)
                derived = any(derived_above(files[p], site)
                              for name in named for p, site in definition_sites(name))
            if not derived:
                failures.append(where + ' (a tolerance without a comment that derives it)')
        k = end + 1

for f in failures:
    print('FAIL: ' + f)
sys.exit(1 if failures else 0)
PYTHON
