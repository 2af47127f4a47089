#!/usr/bin/env bash
# The test command: installs what is missing, builds, runs the whole suite through ctest.
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/build.sh
cd build
ctest --output-on-failure --parallel "$(nproc)" "$@"
