#!/usr/bin/env bash
# Installs what flexref needs on Debian 12 (only what is missing) and builds it in build/.
# Usage: scripts/setup.sh [--target NAME]... [--packages-only] [extra cmake arguments]
#   --target NAME     build only this target (repeatable; default: everything: the library, the
#                     command line, the tests and the benchmarks)
#   --packages-only   install what is missing and build nothing (the test command, before its build)
set -euo pipefail
cd "$(dirname "$0")/.."

targets=()
cmake_args=()
packages_only=0
while (($#)); do
  case $1 in
    --target) targets+=(--target "$2"); shift 2 ;;
    --packages-only) packages_only=1; shift ;;
    *) cmake_args+=("$1"); shift ;;
  esac
done

packages=(build-essential cmake ninja-build libsundials-dev libsuitesparse-dev libeigen3-dev
          libboost-dev libcli11-dev catch2
          libtoml11-dev libbenchmark-dev python3-matplotlib python3-numpy pybind11-dev
          python3-pybind11 python3-dev calculix-ccx libopenmpi-dev openmpi-bin)
# The engines the examples verify (docs/engines.md) are needed only when everything is built:
# the main job (--target flexref) does not wait for their installation.
((${#targets[@]})) || packages+=(libmujoco-dev libsimbody-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq "${missing[@]}" >/dev/null
fi
((packages_only == 0)) || exit 0

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# Ninja for a new build folder: it compiles a target's sources while the libraries they link are
# still compiling, where make builds target after target and leaves a core idle (an existing
# folder keeps the generator it was made with).
generator=()
[[ -f build/CMakeCache.txt ]] || ! command -v ninja >/dev/null || generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "${cmake_args[@]}" >/dev/null
cmake --build build -j"$(nproc)" "${targets[@]}"
