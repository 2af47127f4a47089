#!/usr/bin/env bash
# Installs the Debian 12 packages armstudy needs, only those missing. Runs apt-get as root, or via
# sudo when not root. Safe to run repeatedly.
set -euo pipefail
PKGS=(build-essential cmake ninja-build ccache git pkg-config
      libeigen3-dev libnlopt-cxx-dev libcgal-dev libgmp-dev libmpfr-dev libvtk9-dev
      libtomlplusplus-dev libcli11-dev nlohmann-json3-dev catch2
      libcairo2-dev libfreetype-dev fonts-dejavu-core  # figures: cairo, the font read with FreeType
      fontconfig  # fc-match: the test that a rank with another font configuration writes the same bytes
      chromium chromium-driver  # the browser test of report.html (tests/browser)
      libjs-three  # three.js, inlined into each study's interactive 3-D view (view.html)
      xvfb xauth  # xvfb-run: the ParaView scene render test (scripts/unpack-paraview.sh)
      liborocos-kdl-dev libfcl-dev libceres-dev
      liburdfdom-dev liburdfdom-tools libtinyxml-dev libconsole-bridge-dev libassimp-dev libkdl-parser-dev
      libopenmpi-dev openmpi-bin
      clang-format  # scripts/check-format.sh, run by .ci/run
      python3  # the distribution simulator's tests (tests/study/interleave_test.cpp)
      python3-dev pybind11-dev python3-numpy  # the Python module (src/python, docs/python.md)
      python3-pykdl)  # orocos-kdl from Python: the oracle of the Python module's tests
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
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
