#!/usr/bin/env bash
# The C++ package as a user gets it: `cmake --install` into a temporary prefix, then
#   1. every installed header compiles with only <prefix>/include on the path (one TU);
#   2. examples/cpp (a user's Lie-Euler stepper, registered and studied, and its conformance
#      suite in one line when Catch2 is there) configures, builds and runs against the
#      installed package (find_package(flexref), flexref::flexref);
#   3. the installed Python module imports from the prefix (when it was built).
# A sanitized build's package carries the sanitizers' link options to its users
# (cmake/FlexrefInstall.cmake); its Python module needs ASan's runtime preloaded, which
# FLEXREF_PYTHON_PRELOAD gives (VAR=value words, set by the test's registration).
# Usage: install_test.sh BUILD_DIR (from the repository root).
set -euo pipefail
build=$(cd "$1" && pwd)
src=$PWD
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

cmake --install "$build" --prefix "$prefix" >"$tmp/install.log"
[[ -f $prefix/lib/cmake/flexref/flexrefConfig.cmake ]] || { echo "FAIL: no package config"; exit 1; }
[[ -f $prefix/include/flexref/core/model.hpp ]] || { echo "FAIL: no include/flexref/core"; exit 1; }
[[ ! -e $prefix/include/flexref/reference/sundials_handle.hpp ]] ||
  { echo "FAIL: an internal header was installed"; exit 1; }
if grep -rn '#include "\(io\|rotation\|flexible\|core\|contact\|lie\|reference\|trajectory\|scene\|studies\|precision\)/' \
  "$prefix/include/flexref"; then
  echo "FAIL: installed headers include project paths without the flexref/ prefix"; exit 1
fi

cmake -S "$src/tests/install" -B "$tmp/headers" -DCMAKE_PREFIX_PATH="$prefix" \
  -DFLEXREF_PREFIX="$prefix" "${launcher[@]}" >"$tmp/headers.log" ||
  { cat "$tmp/headers.log"; echo "FAIL: header check configure"; exit 1; }
cmake --build "$tmp/headers" -j2 >"$tmp/headers_build.log" 2>&1 ||
  { tail -30 "$tmp/headers_build.log"; echo "FAIL: installed headers do not compile"; exit 1; }

# The example compiled as the package was: its build type and that type's flags (Release's -O3
# from a Release build; -O1 from the sanitized build, whose sanitizers the package carries).
build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt")
build_type=${build_type:-Release}
type_flags=$(sed -n "s/^CMAKE_CXX_FLAGS_${build_type^^}:[A-Z]*=//p" "$build/CMakeCache.txt")
cmake -S "$src/examples/cpp" -B "$tmp/example" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE="$build_type" "-DCMAKE_CXX_FLAGS_${build_type^^}=$type_flags" \
  "${launcher[@]}" >"$tmp/example.log" ||
  { cat "$tmp/example.log"; echo "FAIL: example configure"; exit 1; }
cmake --build "$tmp/example" -j2 >"$tmp/example_build.log" 2>&1 ||
  { tail -30 "$tmp/example_build.log"; echo "FAIL: example build"; exit 1; }
"$tmp/example/study_lie_euler" scenes/free_spin.toml || { echo "FAIL: example run"; exit 1; }
if [[ -x $tmp/example/conformance_lie_euler ]]; then
  "$tmp/example/conformance_lie_euler" | tail -2 || { echo "FAIL: conformance of the user's stepper"; exit 1; }
fi

module=$(find "$prefix" -name 'flexref*.so' | head -1)
if [[ -n $module ]]; then
  # shellcheck disable=SC2086  # FLEXREF_PYTHON_PRELOAD: VAR=value words (a sanitized build's)
  env ${FLEXREF_PYTHON_PRELOAD:-} PYTHONPATH=$(dirname "$module") /usr/bin/python3 -c 'import flexref; print("python module", flexref.__version__, "imports from the prefix")' ||
    { echo "FAIL: installed Python module"; exit 1; }
fi
echo "install test: 3 passed, 0 failed"
