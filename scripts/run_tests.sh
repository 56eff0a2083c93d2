#!/bin/bash
# Run every unit test (pytest, no master) and every rostest suite (rostest, as catkin's
# run_tests targets call it, results in catkin's results dir), lint the package (catkin_lint --strict -W2, one more test case;
# vermin -t=3.8-, one more; vulture at 60 %, one more), run the Python lanes
# (scripts/python_lane.sh 3.8, 3.12, 3.13: the unit tests, harness missions and mission
# rostests under Noetic's, ROS-O's and Debian trixie's Python), then print one summary
# line `N passed, N failed`.
# Exit status is non-zero on any failure or when no test ran.
#
# Two parts at once (docs/testing.md, "Where the time goes"):
# 1. nothing timed, at nice 19: first install_space.test's `catkin_make install`
#    (scripts/install_space.sh; the test waits for it), then the unit tests and the lint,
#    beside the lanes' unit parts (each its set-up: venv, workspace; unit tests and
#    harness): CPU-bound jobs that take the CPU only when the rostests leave it (they
#    mostly wait on the fake's clock);
# 2. the rostests, one suite at a time at the normal priority (catkin_make run_tests'
#    default `-j<cores> -l<cores>` would start a second suite whenever the load dips): two fake
#    robots at rtf 5-10 on a 2-core machine starve each other's timing (a CI failure: a
#    detection 1.16 s late beside another suite). Behaviour under load is checked on
#    purpose, in the suites that load the machine themselves and in docs/cost.md's runs.
#    Then, once part 1 is done, the lanes' mission rostests, likewise one at a time.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
results="$BN_WS/build/test_results/blind_navigation"
rm -rf "$results"
mkdir -p "$results"

source "$repo/scripts/venvs.sh"   # LANE_PYTHONS
echo "run_tests: unit tests and lint at nice 19 beside the rostests (logs: $BN_WS/test_unit.log, $BN_WS/lane_*_unit.log)"
unit_status="$BN_WS/test_unit.status"
rm -f "$unit_status"
export BN_INSTALL_SPACE="$BN_WS/install_space"
rm -f "$BN_INSTALL_SPACE/build.status"
(
  renice -n 19 -p "$BASHPID" > /dev/null
  bash "$repo/scripts/install_space.sh" "$BN_INSTALL_SPACE"
  lane_units=()
  for version in $LANE_PYTHONS; do
    bash "$repo/scripts/python_lane.sh" "$version" unit "$results" > "$BN_WS/lane_${version}_unit.log" 2>&1 &
    lane_units+=($!)
  done
  # pytest as CMakeLists' run_tests_blind_navigation_pytest runs it (not through a second
  # catkin_make in the build directory the rostests' catkin_make uses)
  /usr/bin/python3 -m pytest -q -p no:cacheprovider "$repo/test/unit" \
    --junitxml="$results/pytest-unit.xml" > "$BN_WS/test_unit.log" 2>&1
  echo $? > "$unit_status"
  # the workspace's link: catkin_lint wants the package in a directory named after it
  /usr/bin/python3 "$repo/scripts/catkin_lint_junit.py" "$BN_WS/src/blind_navigation" \
    "$results/lint-catkin_lint.xml"
  /usr/bin/python3 "$repo/scripts/vermin_junit.py" "$BN_WS/venvs/tools/bin/vermin" "$repo" \
    "$results/lint-vermin.xml"
  /usr/bin/python3 "$repo/scripts/vulture_junit.py" "$BN_WS/venvs/tools/bin/vulture" "$repo" \
    "$results/lint-vulture.xml"
  wait "${lane_units[@]}"
) > "$BN_WS/test_lint.log" 2>&1 &
part1=$!

echo "run_tests: rostests, one at a time (log: $BN_WS/test.log)"
# every test/rostest/*.test, as CMakeLists.txt's add_rostest globs them and catkin's
# run_tests target calls rostest, without make's pass over the workspace per test
rostest_status=0
: > "$BN_WS/test.log"
for test in "$BN_WS/src/blind_navigation"/test/rostest/*.test; do
  name=$(basename "$test" .test)
  rostest --pkgdir="$BN_WS/src/blind_navigation" --package=blind_navigation \
    --results-filename "test_rostest_$name.xml" --results-base-dir "$BN_WS/build/test_results" \
    "$test" >> "$BN_WS/test.log" 2>&1 || rostest_status=1
  [ -f "$results/rostest-test_rostest_$name.xml" ] || {
    rostest_status=1
    /usr/bin/python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); from junit_case import write_case
write_case(sys.argv[2], "rostest", "rostest " + sys.argv[3], sys.argv[3], 1, ["rostest wrote no result"], "")' \
      "$repo/scripts" "$results/MISSING-$name.xml" "$name.test"; }
done
wait $part1
cat "$BN_WS/test_lint.log"
for version in $LANE_PYTHONS; do cat "$BN_WS/lane_${version}_unit.log"; done
status=$(cat "$unit_status" 2>/dev/null || echo 1)
for version in $LANE_PYTHONS; do bash "$repo/scripts/python_lane.sh" "$version" rostests "$results"; done
/usr/bin/python3 "$repo/scripts/test_summary.py" "$results"
summary=$?
[ $status -eq 0 ] || { tail -30 "$BN_WS/test_unit.log"
  echo "run_tests: the unit tests (pytest) exited $status" >&2; }
[ $rostest_status -eq 0 ] || { tail -30 "$BN_WS/test.log"
  echo "run_tests: a rostest failed (log: $BN_WS/test.log)" >&2; }
[ $status -eq 0 ] && [ $rostest_status -eq 0 ] && [ $summary -eq 0 ]
