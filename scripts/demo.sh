#!/bin/bash
# make demo: the gyro is calibrated once (calibrate_gyro.launch on the fake, as a
# user does once per robot), then the fake TurtleBot (paper noise, faster than
# real time) records a Table VI mission, vision fails, the layer stands still to
# measure the gyro bias, turns by pi and travels back; prints a Table-VI-style
# row and writes results/demo_<scenario>_<control>.{txt,png}.
# Override with SCENARIO=table6_test2 CONTROL=time RTF=5 SEED=0 make demo.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
mkdir -p "$repo/results"
export BN_RESULTS_DIR="$repo/results"
seed=${SEED:-0}
calibration="$repo/results/gyro_calibration.yaml"
rm -f "$calibration"   # this demo's own calibration, not a stale one
roslaunch blind_navigation fake_gyro_calibration.launch seed:=$((seed + 10000)) \
  calibration_file:="$calibration" 2>&1 | grep -E '/calibrate_gyro: (spinning|gyro calibration)|ERROR|FATAL' || true
[ -f "$calibration" ] || { echo "demo: the gyro calibration failed (see above)" >&2; exit 1; }
exec roslaunch --screen blind_navigation demo.launch scenario:="${SCENARIO:-table6_test1}" \
  control:="${CONTROL:-closed_loop}" rtf:="${RTF:-5}" seed:="$seed" \
  gyro_calibration_file:="$calibration"
