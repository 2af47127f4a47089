#!/bin/sh
# Model versus measurement for whole arms (docs/calibration.md, "Arms"): a virtual robot with hidden
# effects, then compare -> fit --auto -> compare the calibrated copy (into <kind>/calibrated/, where
# the study puts it), for the tcp and trajectory kinds.
# Usage: studies/arm_calibration.sh [path/to/armstudy] [output folder]
set -e
ARMSTUDY=${1:-build/src/armstudy}
OUT=${2:-output/arm_calibration}
DESIGN=designs/final_prototype_7dof.toml
mkdir -p "$OUT"
# TCP poses: a 10 mrad offset of j3 and a 5 mm error of the j4 table entry x, 0.2 mm noise.
"$ARMSTUDY" synth "$DESIGN" --kind tcp --rows 60 --noise 2e-4 --seed 1 \
  --hide joint_offset.j3:offset=0.01 --hide link_length.j4.x:dx=0.005 --out "$OUT/tcp.csv"
"$ARMSTUDY" compare "$DESIGN" --kind tcp --data "$OUT/tcp.csv" --out "$OUT/tcp"
"$ARMSTUDY" fit "$DESIGN" --kind tcp --data "$OUT/tcp.csv" --auto --out "$OUT/tcp"
"$ARMSTUDY" compare "$OUT/tcp/final_prototype_7dof_calibrated.toml" --kind tcp --data "$OUT/tcp.csv" \
  --out "$OUT/tcp/calibrated"
# Trajectory with motor currents: a 0.5 kg payload and a Stribeck term on j3, 0.01 A noise.
"$ARMSTUDY" synth "$DESIGN" --kind trajectory --duration 4 --rate 100 --currents --noise 0.01 --seed 1 \
  --hide payload --hide j3.stribeck --out "$OUT/run.csv"
"$ARMSTUDY" compare "$DESIGN" --kind trajectory --data "$OUT/run.csv" --out "$OUT/trajectory"
"$ARMSTUDY" fit "$DESIGN" --kind trajectory --data "$OUT/run.csv" --auto --out "$OUT/trajectory"
"$ARMSTUDY" compare "$OUT/trajectory/final_prototype_7dof_calibrated.toml" --kind trajectory --data "$OUT/run.csv" \
  --out "$OUT/trajectory/calibrated"
