#!/usr/bin/env bash
# Every Catch2 test case name must survive ctest's discovery (CMake's CatchAddTests splits the
# listing as a CMake list): a ';', or a '[' or ']' without its partner, silently merges the
# following test cases into one ctest entry that runs none of them.
# Usage: test_names_check.sh PROGRAM...
set -euo pipefail
status=0
for program in "$@"; do
  while IFS= read -r name; do
    open=${name//[^\[]/}
    close=${name//[^\]]/}
    if [[ $name == *";"* || ${#open} -ne ${#close} ]]; then
      echo "FAIL: $(basename "$program"): test name '$name' has a ';' or unbalanced brackets"
      status=1
    fi
  done < <("$program" --list-test-names-only)
done
exit $status
