#!/usr/bin/env bash
# Installs the Debian 12 packages armstudy needs, only those missing. Runs apt-get as root, or via
# sudo when not root. Safe to run repeatedly.
#   scripts/install-deps.sh          # everything: the build, the Python module and the test tools
#   scripts/install-deps.sh --study  # what configuring and building the armstudy program needs
#                                    # (./run-study.sh): no test oracles, browser, Xvfb, formatter,
#                                    # benchmark peers or Python module
set -euo pipefail
STUDY_ONLY=0
[ "${1:-}" = "--study" ] && STUDY_ONLY=1
PKGS=(build-essential cmake ninja-build ccache git pkg-config
      libeigen3-dev libnlopt-cxx-dev libcgal-dev libgmp-dev libmpfr-dev libvtk9-dev
      libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
      libcairo2-dev libfreetype-dev fonts-dejavu-core  # figures: cairo, the font read with FreeType
      libjs-three  # three.js, inlined into each study's interactive 3-D view (view.html)
      liburdfdom-dev libtinyxml-dev libconsole-bridge-dev libassimp-dev  # URDF import, meshes
      libopenmpi-dev openmpi-bin)  # distributed runs (docs/distributed.md)
# Only the tests, the benchmarks, the Python module and CI use these (the study command does not
# install them, and configures without tests, benchmarks and Python module):
TEST_PKGS=(catch2
           liborocos-kdl-dev libkdl-parser-dev liburdfdom-tools  # the kinematics and URDF oracles
           libfcl-dev libceres-dev  # peers of the collision and calibration benchmarks
           fontconfig  # fc-match: the test that a rank with another font configuration writes the same bytes
           python3  # the distribution simulator's tests (tests/study/interleave_test.cpp)
           python3-dev pybind11-dev python3-numpy  # the Python module (src/python, docs/python.md)
           chromium chromium-driver  # the browser test of report.html (tests/browser)
           xvfb xauth  # xvfb-run: the ParaView scene render test (scripts/unpack-paraview.sh)
           clang-format  # scripts/check-format.sh, run by .ci/run
           python3-pykdl  # orocos-kdl from Python: the oracle of the Python module's tests
           jupyter-nbconvert python3-ipykernel)  # the notebook docs/python.ipynb, run by ctest
[ "$STUDY_ONLY" = 1 ] || PKGS+=("${TEST_PKGS[@]}")
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
echo "armstudy: installing missing Debian packages: ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# --force-unsafe-io: dpkg skips its fsync after each file. Unpacking and configuring the program's
# packages on a new machine took 203 s instead of 445 s at load average 15 (docs/performance.md,
# "Build and CI").
# A machine that loses power mid-install may need the install run again.
$SUDO apt-get install -y -qq --no-install-recommends -o Dpkg::Options::=--force-unsafe-io \
  "${missing[@]}" >/dev/null
