#!/bin/bash
# The Noetic lane of make test (docs/testing.md): under Python 3.8 with Ubuntu 20.04's
# numpy and PyYAML (the py38 venv, scripts/venvs.sh) over Debian's pure-Python ROS
# libraries, in a workspace built with that interpreter ($BN_WS/py38_ws), run
#   - the unit tests (pytest-py38-unit.xml),
#   - test/noetic's harness missions (pytest-py38-lane.xml),
#   - test/noetic/py38_*.test: mission rostests with every node and test script under
#     3.8 (each checks so: interpreter_check.py), results as rosunit-py38-*.xml,
# all into catkin's results dir, which scripts/test_summary.py counts.
#   noetic_lane.sh [all|unit|rostests] [RESULTS_DIR]
# unit: the set-up (venv, workspace), the unit tests and the harness: no timing in them, so
# make test runs this part beside the main unit tests and lint; rostests: the mission
# rostests, each alone on the machine, after the unit part. all (the default): both.
# Without a Python 3.8 it says so in one line (in the unit part) and exits 0.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
source "$repo/scripts/venvs.sh"
part="${1:-all}"
case "$part" in all|unit|rostests) ;; *) echo "noetic_lane: unknown part '$part' (all, unit or rostests)" >&2; exit 2;; esac
results="${2:-$BN_WS/build/test_results/blind_navigation}"
python38=$(find_python38) || {
  [ "$part" = rostests ] || \
    echo "noetic_lane: no Python 3.8 here (pyenv's versions/3.8.*, python3.8 on PATH): lane skipped"
  exit 0; }
start=$SECONDS
# the set-up as one test case, so that a lane that cannot start fails make test
setup_case() {
  /usr/bin/python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); from junit_case import write_case
write_case(sys.argv[2], "noetic_lane", "noetic_lane set-up", sys.argv[3], int(sys.argv[4]), sys.argv[5:], "")' \
    "$repo/scripts" "$results/lint-noetic_lane.xml" "$python38" "$@"
}
fail() { echo "noetic_lane: $1" >&2; setup_case 1 "$1"; exit 1; }
venv="$BN_WS/venvs/py38" ws="$BN_WS/py38_ws"

# A clean environment: the lane's python3 first on PATH, only the py38 workspace sourced.
lane() {
  env -i HOME="$HOME" TERM="${TERM:-dumb}" PATH="$venv/bin:/usr/bin:/bin" ROS_PYTHON_VERSION=3 \
    ROS_HOME="$ws/ros_home" ROS_LOG_DIR="$ws/log" BN_WS="$BN_WS" bash -c '
      [ -f /opt/ros/noetic/setup.bash ] && source /opt/ros/noetic/setup.bash
      [ -f "$0/devel/setup.bash" ] && source "$0/devel/setup.bash"
      "$@"' "$ws" "$@"
}
status=0
if [ "$part" != rostests ]; then
  make_venv py38 "$python38" py38.txt && debian_ros_behind "$venv" || fail "no py38 venv"
  mkdir -p "$ws/src" "$results"
  [ -e "$ws/src/blind_navigation" ] || ln -s "$repo" "$ws/src/blind_navigation"
  lane catkin_make -C "$ws" -DPYTHON_EXECUTABLE="$venv/bin/python3" -DCATKIN_ENABLE_TESTING=OFF \
    -DCMAKE_BUILD_TYPE=Release > "$ws/build.log" 2>&1 || {
      tail -20 "$ws/build.log"; fail "catkin_make with $venv/bin/python3 failed ($ws/build.log)"; }
  # The fake TurtleBot's base and camera (the test rig, not the layer) broadcast TF with
  # tf2_ros, whose tf2_py._tf2 is a C extension Debian builds for its Python 3.11 only:
  # they run under /usr/bin/python3 (their relays' shebang); every other node under 3.8.
  for rig in fake_kobuki.py fake_vision.py; do
    sed -i '1s|^#!.*|#!/usr/bin/python3|' "$ws/devel/lib/blind_navigation/$rig"
  done
  # as scripts/build.sh does for Debian's Python: the nodes' modules compiled once
  "$venv/bin/python3" -m compileall -q "$repo/blind_navigation" "$repo/test/rostest" "$repo/test/noetic" \
    > /dev/null
  echo "noetic_lane: $("$venv/bin/python3" --version) ($python38), workspace $ws"
  setup_case 0

  # the venv's pytest script: `python -m pytest` would put the repo first on sys.path,
  # ahead of the workspace's package (which has the generated messages)
  lane pytest -q -p no:cacheprovider "$repo/test/unit" --junitxml="$results/pytest-py38-unit.xml" \
    > "$ws/pytest-unit.log" 2>&1 || status=1
  lane pytest -q -p no:cacheprovider "$repo/test/noetic" --junitxml="$results/pytest-py38-lane.xml" \
    > "$ws/pytest-lane.log" 2>&1 || status=1
  echo "noetic_lane: unit tests: $(tail -qn1 "$ws/pytest-unit.log"); harness: $(tail -qn1 "$ws/pytest-lane.log")"
fi

if [ "$part" != unit ]; then
  [ -x "$ws/devel/lib/blind_navigation/fake_kobuki.py" ] || fail "no py38 workspace: run the unit part first"
  mkdir -p "$ws/rostest"
  for test in "$repo"/test/noetic/py38_*.test; do
    out="$ws/rostest/$(basename "$test" .test)"
    rm -rf "$out"
    lane rostest --results-base-dir "$out" "$test" > "$out.log" 2>&1 || status=1
    /usr/bin/python3 "$repo/scripts/py38_results.py" "$out/blind_navigation" "$results" py38- \
      || status=1
    echo "noetic_lane: $(basename "$test"):$(sed 's/\x1b\[[0-9;]*m//g' "$out.log" | grep -E '^ \* (RESULT|TESTS|FAILURES|ERRORS):' | cut -c3- | tr '\n' ' ')(log: $out.log)"
  done
fi
echo "noetic_lane: $part done in $((SECONDS - start)) s"
exit $status
