#!/usr/bin/env bash
# The main job: installs what is missing, builds the armstudy program (not the tests), runs a study (default: the spraying row of
# thesis Fig. 3.8) and writes its results under output/<study name>/.
#   ./run-study.sh                        # studies/default.toml
#   ./run-study.sh studies/X.toml [opts]  # any study; options go to `armstudy run`
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/build.sh --study >/dev/null
study="${1:-studies/default.toml}"
shift || true
exec ./build/src/armstudy run "$study" --overwrite "$@"
