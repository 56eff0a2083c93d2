#!/bin/bash
# make bench: the evaluation (docs/evaluation.md). Runs after `make build` (the
# Makefile's bench target): the Monte-Carlo reproduction of the paper's Tables
# III-VI on the plain-Python harness, reconstruction, storage, TUM files and
# figures, then the ROS runs (launch/bench.launch); writes results/.
# Options via BENCH_ARGS, e.g. BENCH_ARGS="--seeds 20 --no-ros" make bench.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
mkdir -p "$repo/results"
cd "$repo"
start=$(date +%s)
# shellcheck disable=SC2086
/usr/bin/python3 -m blind_navigation.evaluation.bench --out "$repo/results" ${BENCH_ARGS:-} \
  2>&1 | tee "$repo/results/bench.log"
echo "bench: make bench took $(( $(date +%s) - start )) s; report: results/report.md"
