#!/usr/bin/env bash
# The sanitizer subset (README "Sanitizers", docs/hardening.md): AddressSanitizer +
# UndefinedBehaviorSanitizer (leak detection on) over the parsers, their fuzz replays, the
# kinematics and dynamics kernels, the checkpoint store and one SIGKILL/resume run of the sanitized
# armstudy (tests/CMakeLists.txt, sanitizer_subset), in build-asan/. CI runs it after the suite;
# the whole suite under the sanitizers (about an hour on 2 cores) stays a manual run (README).
set -euo pipefail
cd "$(dirname "$0")/.."
B=build-asan
GEN=()
command -v ninja >/dev/null && GEN=(-G Ninja)
if [ ! -f "$B/CMakeCache.txt" ]; then
  # -Og: under the sanitizers half the compile time of -O1 (the subset's time is in the parsers,
  # not in optimised kernels); Eigen asserts stay on (no NDEBUG); unity batches as scripts/build.sh.
  # Build and run times:
  # docs/performance.md, "Build and CI".
  cmake -S . -B "$B" "${GEN[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-Og -DARMSTUDY_SANITIZE=ON \
        -DARMSTUDY_UNITY="${ARMSTUDY_UNITY:-ON}" -DARMSTUDY_BUILD_BENCHMARKS=OFF >/dev/null
fi
start=$(date +%s)
cmake --build "$B" --parallel "$(nproc)" --target sanitizer_subset
echo "sanitizer subset: built in $(( $(date +%s) - start )) s" >&2
cd "$B"
# Halt on the first report: a sanitizer finding fails the test that caused it.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --output-on-failure --parallel "$(nproc)" -R '^sanitizer subset:'
echo "sanitizer subset: done in $(( $(date +%s) - start )) s" >&2
