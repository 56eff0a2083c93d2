#!/bin/bash
# Run every unit test (pytest, no master) and every rostest suite through catkin's
# run_tests targets, lint the package (catkin_lint --strict -W2, one more test case;
# vermin -t=3.8-, one more; vulture at 60 %, one more), run the Python lanes
# (scripts/python_lane.sh 3.8, 3.12, 3.13: the unit tests, harness missions and mission
# rostests under Noetic's, ROS-O's and Debian trixie's Python), then print one summary
# line `N passed, N failed`.
# Exit status is non-zero on any failure or when no test ran.
#
# Two phases (docs/testing.md, "Where the time goes"):
# 1. nothing timed: the unit tests and the lint here, beside the lanes' unit parts (each
#    its set-up, unit tests and harness) in the background, all at once: single-threaded
#    CPU-bound jobs sharing the two cores;
# 2. the rostests, one suite at a time and nothing beside them: catkin_make's default
#    `-j<cores> -l<cores>` starts a second suite whenever the load dips, and two fake
#    robots at rtf 5-10 on a 2-core machine starve each other's timing (a CI failure: a
#    detection 1.16 s late beside another suite). Behaviour under load is checked on
#    purpose, in the suites that load the machine themselves and in docs/cost.md's runs.
#    Then the lanes' mission rostests, likewise one at a time.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
results="$BN_WS/build/test_results/blind_navigation"
rm -rf "$results"
mkdir -p "$results"

source "$repo/scripts/venvs.sh"   # LANE_PYTHONS
echo "run_tests: unit tests and lint, beside the lanes' unit parts (logs: $BN_WS/lane_*_unit.log)"
lane_units=()
for version in $LANE_PYTHONS; do
  bash "$repo/scripts/python_lane.sh" "$version" unit "$results" > "$BN_WS/lane_${version}_unit.log" 2>&1 &
  lane_units+=($!)
done
catkin_make -C "$BN_WS" run_tests_blind_navigation_pytest > "$BN_WS/test_unit.log" 2>&1
status=$?
# the workspace's link: catkin_lint wants the package in a directory named after it
/usr/bin/python3 "$repo/scripts/catkin_lint_junit.py" "$BN_WS/src/blind_navigation" \
  "$results/lint-catkin_lint.xml"
/usr/bin/python3 "$repo/scripts/vermin_junit.py" "$BN_WS/venvs/tools/bin/vermin" "$repo" \
  "$results/lint-vermin.xml"
/usr/bin/python3 "$repo/scripts/vulture_junit.py" "$BN_WS/venvs/tools/bin/vulture" "$repo" \
  "$results/lint-vulture.xml"
wait "${lane_units[@]}"
for version in $LANE_PYTHONS; do cat "$BN_WS/lane_${version}_unit.log"; done

echo "run_tests: rostests, one at a time (log: $BN_WS/test.log)"
catkin_make -C "$BN_WS" run_tests_blind_navigation_rostest -j1 -l1 > "$BN_WS/test.log" 2>&1
rostest_status=$?
for version in $LANE_PYTHONS; do bash "$repo/scripts/python_lane.sh" "$version" rostests "$results"; done
/usr/bin/python3 "$repo/scripts/test_summary.py" "$results"
summary=$?
[ $status -eq 0 ] || { tail -30 "$BN_WS/test_unit.log"
  echo "run_tests: catkin_make run_tests_blind_navigation_pytest exited $status" >&2; }
[ $rostest_status -eq 0 ] || { tail -30 "$BN_WS/test.log"
  echo "run_tests: catkin_make run_tests_blind_navigation_rostest exited $rostest_status" >&2; }
[ $status -eq 0 ] && [ $rostest_status -eq 0 ] && [ $summary -eq 0 ]
