#!/bin/bash
# make demo: the gyro is calibrated once (calibrate_gyro.launch on the fake, as a
# user does once per robot), then the fake TurtleBot (paper noise, faster than
# real time) records a Table VI mission, vision fails, the layer stands still to
# measure the gyro bias, turns by pi and travels back; prints a Table-VI-style
# row and writes results/demo_<scenario>_<control>.{txt,png}.
# Override with SCENARIO=table6_test2 CONTROL=time RTF=5 SEED=0 make demo.
#
# The demo runs on a master of its own (a free port), so it never sets
# /use_sim_time on a master the user runs. demo.launch runs in the background
# without its observer; the observer (demo_observer.py, the same params) runs in
# the foreground and its exit status is the demo's: 0 when the robot came home.
# Then the launch is stopped with SIGINT, as Ctrl-C would.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
mkdir -p "$repo/results"
export BN_RESULTS_DIR="$repo/results"
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("localhost", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI="http://localhost:$port"
seed=${SEED:-0}
scenario=${SCENARIO:-table6_test1}
control=${CONTROL:-closed_loop}
calibration="$repo/results/gyro_calibration.yaml"
rm -f "$calibration"   # this demo's own calibration, not a stale one
roslaunch blind_navigation fake_gyro_calibration.launch seed:=$((seed + 10000)) rtf:="${RTF:-5}" \
  calibration_file:="$calibration" 2>&1 | grep -E '/calibrate_gyro: (spinning|gyro calibration)|ERROR|FATAL' || true
[ -f "$calibration" ] || { echo "demo: the gyro calibration failed (see above)" >&2; exit 1; }

roslaunch --screen blind_navigation demo.launch observer:=false scenario:="$scenario" \
  control:="$control" rtf:="${RTF:-5}" seed:="$seed" gyro_calibration_file:="$calibration" &
launch=$!
stop_launch() {
  if kill -0 "$launch" 2>/dev/null; then
    kill -INT "$launch"
    wait "$launch" || true
  fi
}
trap stop_launch EXIT

# the observer needs the launch's parameters (/use_sim_time above all) before it starts
for _ in $(seq 300); do
  rosparam get /use_sim_time >/dev/null 2>&1 && break
  kill -0 "$launch" 2>/dev/null || { echo "demo: demo.launch ended early (see above)" >&2; exit 1; }
  sleep 0.1
done
rosparam get /use_sim_time >/dev/null 2>&1 || { echo "demo: no master at $ROS_MASTER_URI after 30 s" >&2; exit 1; }

# as roslaunch finds it (rosrun would also search the workspace inside the repo)
observer=$(catkin_find --first-only --libexec blind_navigation demo_observer.py)
"$observer" _scenario:="$scenario" _control:="$control" _results_dir:="$BN_RESULTS_DIR" &
observing=$!
# the observer waits in sim time: if the launch ends (a required node died), no clock is left
while kill -0 "$observing" 2>/dev/null; do
  if ! kill -0 "$launch" 2>/dev/null; then
    echo "demo: demo.launch ended before the observer's report (see above)" >&2
    kill -INT "$observing"
    break
  fi
  sleep 1
done
status=0
wait "$observing" || status=$?
stop_launch
if [ "$status" -eq 0 ]; then
  echo "demo: the robot came home"
else
  echo "demo: the robot did not come home (demo_observer exit status $status)" >&2
fi
exit "$status"
