#!/usr/bin/env bash
# Configures and builds armstudy (Release) into build/. Installs missing packages first.
#   scripts/build.sh          # everything: the program, the Python module, the tests (./run-tests.sh)
#   scripts/build.sh --study  # the armstudy program only, with only the packages it needs (./run-study.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
TARGET=()
if [ "${1:-}" = "--study" ]; then
  bash scripts/install-deps.sh --study
  TARGET=(--target armstudy)
else
  bash scripts/install-deps.sh
  bash scripts/unpack-paraview.sh build/paraview  # pvpython for the scene render test
fi
GEN=()
command -v ninja >/dev/null && GEN=(-G Ninja)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build "${GEN[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build build --parallel "$(nproc)" "${TARGET[@]}"
