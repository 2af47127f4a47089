#!/usr/bin/env bash
# Unpacks Debian's ParaView (packages paraview and python3-paraview) into build/paraview/ and writes
# build/paraview/pvpython, a wrapper that runs its pvpython. Not installed system-wide because on
# Debian 12 python3-paraview conflicts with libvtk9-dev, which armstudy builds with (docs/paraview.md).
# Used by tests/study/paraview_scene_test.cpp (the scenes rendered offscreen through xvfb-run).
# Safe to run repeatedly; when apt cannot download, it warns and the render test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
DEST=${1:-build/paraview}
WRAPPER="$DEST/pvpython"
if [ -x "$WRAPPER" ] && "$WRAPPER" -c "import paraview.simple" >/dev/null 2>&1; then exit 0; fi
rm -rf "$DEST.tmp"
mkdir -p "$DEST.tmp/debs"
if ! (cd "$DEST.tmp/debs" && apt-get download paraview python3-paraview >/dev/null 2>&1); then
  echo "armstudy: could not download paraview/python3-paraview with apt-get; the ParaView render test will fail" >&2
  rm -rf "$DEST.tmp"
  exit 0
fi
for deb in "$DEST.tmp"/debs/*.deb; do dpkg-deb -x "$deb" "$DEST.tmp/root"; done
rm -rf "$DEST.tmp/debs"
FINAL_ROOT=$(mkdir -p "$(dirname "$DEST")" && cd "$(dirname "$DEST")" && pwd)/$(basename "$DEST")/root
cat > "$DEST.tmp/pvpython" <<WRAP
#!/bin/sh
# pvpython of the ParaView unpacked by scripts/unpack-paraview.sh
R="$FINAL_ROOT"
export LD_LIBRARY_PATH="\$R/usr/lib/x86_64-linux-gnu/paraview-5.11:\$R/usr/lib/x86_64-linux-gnu\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
export PYTHONPATH="\$R/usr/lib/python3/dist-packages\${PYTHONPATH:+:\$PYTHONPATH}"
exec "\$R/usr/bin/pvpython" "\$@"
WRAP
chmod +x "$DEST.tmp/pvpython"
rm -rf "$DEST"
mv "$DEST.tmp" "$DEST"
if ! "$WRAPPER" -c "import paraview.simple" >/dev/null 2>&1; then
  echo "armstudy: the unpacked ParaView does not start ($WRAPPER); the ParaView render test will fail" >&2
fi
