#!/bin/bash
# Run every unit test (pytest, no master) and every rostest suite through
# `catkin_make run_tests`, lint the package (catkin_lint --strict -W2, one more
# test case), then print one summary line `N passed, N failed`.
# Exit status is non-zero on any failure or when no test ran.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
results="$BN_WS/build/test_results/blind_navigation"
rm -rf "$results"
echo "run_tests: catkin_make run_tests (log: $BN_WS/test.log)"
catkin_make -C "$BN_WS" run_tests > "$BN_WS/test.log" 2>&1
status=$?
# the workspace's link: catkin_lint wants the package in a directory named after it
/usr/bin/python3 "$repo/scripts/catkin_lint_junit.py" "$BN_WS/src/blind_navigation" \
  "$results/lint-catkin_lint.xml"
/usr/bin/python3 "$repo/scripts/test_summary.py" "$results"
summary=$?
if [ $status -ne 0 ]; then
  tail -30 "$BN_WS/test.log"
  echo "run_tests: catkin_make run_tests exited $status" >&2
fi
[ $status -eq 0 ] && [ $summary -eq 0 ]
