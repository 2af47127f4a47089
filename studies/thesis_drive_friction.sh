#!/bin/sh
# Thesis chapter 4 as a model-versus-measurement run (docs/calibration.md, "The thesis story"):
# the catalog friction law of drive j6 (module B.2, eq. 3.30 with Table C.1 CSD-20-100) against the
# B.2 test-bed sample; the loop finds the Stribeck term (eq. 3.33) and the held-out error falls.
# Usage: studies/thesis_drive_friction.sh [path/to/armstudy] [output folder]
set -e
ARMSTUDY=${1:-build/src/armstudy}
OUT=${2:-output/thesis_drive_friction}
DESIGN=designs/final_prototype_9dof.toml
DATA=studies/data/drive_testbed_module_b2.csv
"$ARMSTUDY" compare "$DESIGN" --drive j6 --data "$DATA" --out "$OUT"
"$ARMSTUDY" fit "$DESIGN" --drive j6 --data "$DATA" --auto --out "$OUT"
"$ARMSTUDY" compare "$OUT/final_prototype_9dof_calibrated.toml" --drive j6 --data "$DATA" --out "$OUT"
