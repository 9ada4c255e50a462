#!/usr/bin/env bash
# Every tolerance in a test is explicit and derived (docs/design/style.md, "Tests"): a Catch2
# Approx(x) without .epsilon(…) or .margin(…) compares to Catch2's silent default, a relative
# 1.2e-5 (float's epsilon × 100) that no comment derives. This check fails on every such bare
# Approx in the C++ tests (Eigen's isApprox is not Catch2's and is not matched).
# Usage: approx_check.sh TESTS_DIR
set -euo pipefail
tests=$1
status=0
while IFS= read -r file; do
  # The whole file as one record: an Approx(...) and its .epsilon may be on different lines.
  hits=$(awk '
    BEGIN { RS = "\001" }
    {
      text = $0
      offset = 0
      while ((i = index(text, "Approx(")) > 0) {
        before = (i > 1) ? substr(text, i - 1, 1) : ""
        start = i + 7
        depth = 1
        j = start
        n = length(text)
        while (j <= n && depth > 0) {
          c = substr(text, j, 1)
          if (c == "(") depth++
          else if (c == ")") depth--
          j++
        }
        rest = substr(text, j)
        sub(/^[ \t\n]*/, "", rest)
        if (before !~ /[A-Za-z0-9_:]/ && rest !~ /^\.(epsilon|margin)\(/) {
          prefix = substr(text, 1, i)
          line = offset + 1 + gsub(/\n/, "", prefix)
          print line
        }
        consumed = substr(text, 1, i + 6)
        offset += gsub(/\n/, "", consumed)
        text = substr(text, i + 7)
      }
    }' "$file")
  for line in $hits; do
    echo "FAIL: $file:$line: $(sed -n "${line}p" "$file" | sed 's/^ *//') (a bare Approx: give it .epsilon(…) or .margin(…) and the comment that derives it)"
    status=1
  done
done < <(find "$tests" \( -name '*.cpp' -o -name '*.hpp' \) | sort)
exit $status
