#!/usr/bin/env bash
# Configures and builds armstudy (Release) into build/. Installs missing packages first.
#   scripts/build.sh          # everything: the program, the Python module, the tests (./run-tests.sh)
#   scripts/build.sh --study  # the armstudy program only, with only the packages it needs (./run-study.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
TARGET=()
STUDY=0
# The study build configures without the tests, the benchmarks and the Python module (whose
# packages it does not install); the full build turns them on again in the same build folder.
PARTS=(-DARMSTUDY_BUILD_TESTS=ON -DARMSTUDY_BUILD_BENCHMARKS=ON -DARMSTUDY_PYTHON=ON)
if [ "${1:-}" = "--study" ]; then
  STUDY=1
  bash scripts/install-deps.sh --study
  TARGET=(--target armstudy)
  PARTS=(-DARMSTUDY_BUILD_TESTS=OFF -DARMSTUDY_BUILD_BENCHMARKS=OFF -DARMSTUDY_PYTHON=OFF)
else
  bash scripts/install-deps.sh
  # pvpython for the scene render test, unpacked while the build compiles: mostly a download and
  # disk writes (32 s wall, 12 s CPU), so it costs the build little.
  mkdir -p build
  bash scripts/unpack-paraview.sh build/paraview &
  PARAVIEW=$!
fi
GEN=()
command -v ninja >/dev/null && GEN=(-G Ninja)
# A new build folder compiles in unity batches (CMakeLists.txt, ARMSTUDY_UNITY): less CPU from
# scratch. ARMSTUDY_UNITY=OFF compiles file by file, which a compiler cache shared between clones
# hits more often.
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build "${GEN[@]}" -DCMAKE_BUILD_TYPE=Release -DARMSTUDY_UNITY="${ARMSTUDY_UNITY:-ON}" \
        "${PARTS[@]}" >/dev/null
elif [ "$STUDY" = 0 ] && grep -qE '^ARMSTUDY_(BUILD_TESTS|BUILD_BENCHMARKS|PYTHON):BOOL=OFF' build/CMakeCache.txt; then
  cmake -S . -B build "${PARTS[@]}" >/dev/null  # configured by the study build: everything on
fi
cmake --build build --parallel "$(nproc)" "${TARGET[@]}"
[ "$STUDY" = 1 ] || wait "$PARAVIEW"
