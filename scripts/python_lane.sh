#!/bin/bash
# A Python lane of make test (docs/testing.md, "The Python lanes"): the package under
# Python VERSION with its distribution's numpy and PyYAML (the pyXY venv,
# requirements/pyXY.txt, scripts/venvs.sh) over Debian's pure-Python ROS libraries, in a
# workspace built with that interpreter ($BN_WS/pyXY_ws):
#   3.8   ROS Noetic on Ubuntu 20.04    3.12  ROS-O on Ubuntu 24.04    3.13  Debian trixie
# Each runs
#   - the unit tests (pytest-pyXY-unit.xml),
#   - test/lanes' harness missions (pytest-pyXY-lane.xml),
#   - its mission rostests (test/lanes/lane_MISSION.test, MISSIONS below) with every node
#     and test script under VERSION (lane_mission.py checks so), results as
#     rosunit-pyXY-*.xml,
# all into catkin's results dir, which scripts/test_summary.py counts.
#   python_lane.sh VERSION [all|unit|rostests] [RESULTS_DIR]
# unit: the set-up (venv, workspace), the unit tests and the harness: no timing in them, so
# make test runs this part beside the main unit tests and lint; rostests: the mission
# rostests, each alone on the machine, after the unit part. all (the default): both.
# Without a Python VERSION it says so in one line and as a skipped test case (in the unit
# part) and exits 0.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
source "$repo/scripts/venvs.sh"
version="${1:-}" part="${2:-all}"
case "$version" in
  3.8) missions="mission_closed_loop" ;;      # the one process (the default layer, on Noetic)
  3.12) missions="mission_left_arc_time" ;;   # the paper's layout
  3.13) missions="" ;;
  *) echo "python_lane: unknown Python '$version' (one of $LANE_PYTHONS)" >&2; exit 2 ;;
esac
case "$part" in all|unit|rostests) ;; *) echo "python_lane: unknown part '$part' (all, unit or rostests)" >&2; exit 2;; esac
name="py${version/./}"
results="${3:-$BN_WS/build/test_results/blind_navigation}"
venv="$BN_WS/venvs/$name" ws="$BN_WS/${name}_ws"
say() { echo "python_lane $version: $*"; }
# the set-up as one test case, so that a lane that cannot start fails make test:
#   setup_case TARGET STATUS|skip [PROBLEM...]
setup_case() {
  /usr/bin/python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); from junit_case import write_case
skip = sys.argv[5] == "skip"
write_case(sys.argv[2], "python_lane", sys.argv[3], sys.argv[4], 0 if skip else int(sys.argv[5]), sys.argv[6:],
           "", skipped=sys.argv[6] if skip else None)' \
    "$repo/scripts" "$results/lint-lane-$name.xml" "python_lane $version set-up" "$@"
}
python=$(find_python "$version") || {
  if [ "$part" != rostests ]; then
    message="no Python $version here (pyenv's versions/$version.*, python$version on PATH): lane skipped"
    say "$message"; mkdir -p "$results"; setup_case "python$version" skip "$message"
  fi
  exit 0; }
start=$SECONDS
fail() { echo "python_lane $version: $1" >&2; setup_case "$python" 1 "$1"; exit 1; }

# A clean environment: the lane's python3 first on PATH, only the lane's workspace sourced.
lane() {
  env -i HOME="$HOME" TERM="${TERM:-dumb}" PATH="$venv/bin:/usr/bin:/bin" ROS_PYTHON_VERSION=3 \
    ROS_HOME="$ws/ros_home" ROS_LOG_DIR="$ws/log" BN_WS="$BN_WS" BN_LANE="$name" \
    BN_LANE_PYTHON="$version" bash -c '
      [ -f /opt/ros/noetic/setup.bash ] && source /opt/ros/noetic/setup.bash
      [ -f "$0/devel/setup.bash" ] && source "$0/devel/setup.bash"
      "$@"' "$ws" "$@"
}
status=0
if [ "$part" != rostests ]; then
  make_venv "$name" "$python" "$name.txt" && debian_ros_behind "$venv" || fail "no $name venv"
  mkdir -p "$ws/src" "$results"
  [ -e "$ws/src/blind_navigation" ] || ln -s "$repo" "$ws/src/blind_navigation"
  lane catkin_make -C "$ws" -DPYTHON_EXECUTABLE="$venv/bin/python3" -DCATKIN_ENABLE_TESTING=OFF \
    -DCMAKE_BUILD_TYPE=Release > "$ws/build.log" 2>&1 || {
      tail -20 "$ws/build.log"; fail "catkin_make with $venv/bin/python3 failed ($ws/build.log)"; }
  # The fake TurtleBot's base and camera (the test rig, not the layer) broadcast TF with
  # tf2_ros, whose tf2_py._tf2 is a C extension Debian builds for its Python 3.11 only:
  # they run under /usr/bin/python3 (their relays' shebang); every other node under the lane's.
  for rig in fake_kobuki.py fake_vision.py; do
    sed -i '1s|^#!.*|#!/usr/bin/python3|' "$ws/devel/lib/blind_navigation/$rig"
  done
  # as scripts/build.sh does for Debian's Python: the nodes' modules compiled once
  "$venv/bin/python3" -m compileall -q "$repo/blind_navigation" "$repo/test/rostest" "$repo/test/lanes" \
    > /dev/null
  say "$("$venv/bin/python3" --version) ($python), workspace $ws"
  setup_case "$python" 0

  # the venv's pytest script: `python -m pytest` would put the repo first on sys.path,
  # ahead of the workspace's package (which has the generated messages)
  lane pytest -q -p no:cacheprovider "$repo/test/unit" --junitxml="$results/pytest-$name-unit.xml" \
    > "$ws/pytest-unit.log" 2>&1 || status=1
  lane pytest -q -p no:cacheprovider "$repo/test/lanes" --junitxml="$results/pytest-$name-lane.xml" \
    > "$ws/pytest-lane.log" 2>&1 || status=1
  say "unit tests: $(tail -qn1 "$ws/pytest-unit.log"); harness: $(tail -qn1 "$ws/pytest-lane.log")"
fi

if [ "$part" != unit ] && [ -n "$missions" ]; then
  [ -x "$ws/devel/lib/blind_navigation/fake_kobuki.py" ] || fail "no $name workspace: run the unit part first"
  mkdir -p "$ws/rostest"
  for mission in $missions; do
    out="$ws/rostest/lane_$mission"
    rm -rf "$out"
    lane rostest --results-base-dir "$out" "$repo/test/lanes/lane_$mission.test" > "$out.log" 2>&1 || status=1
    /usr/bin/python3 "$repo/scripts/lane_results.py" "$out/blind_navigation" "$results" "$name-" \
      || status=1
    say "lane_$mission.test:$(sed 's/\x1b\[[0-9;]*m//g' "$out.log" | grep -E '^ \* (RESULT|TESTS|FAILURES|ERRORS):' | cut -c3- | tr '\n' ' ')(log: $out.log)"
  done
fi
say "$part done in $((SECONDS - start)) s"
exit $status
