#!/usr/bin/env bash
# Fails when a C++ file under src/ or tests/ differs from what the project's .clang-format gives
# (Debian clang-format). Fix with: git ls-files 'src/*.[ch]pp' 'tests/*.[ch]pp' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
git ls-files -z 'src/*.cpp' 'src/*.hpp' 'src/*.h' 'tests/*.cpp' 'tests/*.hpp' 'tests/*.h' |
  xargs -0 clang-format --dry-run -Werror
echo "check-format: every C++ file follows .clang-format"
