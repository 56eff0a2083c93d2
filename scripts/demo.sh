#!/bin/bash
# make demo: the fake TurtleBot (paper noise, faster than real time) records a
# Table VI mission, vision fails, the layer turns by pi and travels back; prints
# a Table-VI-style row and writes results/demo_<scenario>_<control>.{txt,png}.
# Override with SCENARIO=table6_test2 CONTROL=time RTF=5 SEED=0 make demo.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
mkdir -p "$repo/results"
export BN_RESULTS_DIR="$repo/results"
exec roslaunch --screen blind_navigation demo.launch scenario:="${SCENARIO:-table6_test1}" \
  control:="${CONTROL:-closed_loop}" rtf:="${RTF:-5}" seed:="${SEED:-0}"
