#!/bin/bash
# Build blind_navigation in a catkin workspace under the repo (.ws by default,
# BN_WS to change it), with the repo linked in as src/blind_navigation.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
source "$repo/scripts/ros_env.sh"
mkdir -p "$BN_WS/src"
if [ ! -e "$BN_WS/src/blind_navigation" ]; then
  ln -s "$repo" "$BN_WS/src/blind_navigation"
fi
catkin_make -C "$BN_WS" -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
  -DCMAKE_BUILD_TYPE=Release "$@" > "$BN_WS/build.log" 2>&1 || {
    tail -40 "$BN_WS/build.log"; echo "build: catkin_make failed (full log: $BN_WS/build.log)" >&2; exit 1; }
# Byte-compile the package and the test rig once: a process started with
# PYTHONDONTWRITEBYTECODE set (as some shells and CI set it) never writes its .pyc
# files, and then every node and test node of make test compiles the modules again.
/usr/bin/python3 -m compileall -q "$repo/blind_navigation" "$repo/test/rostest" > /dev/null
echo "build: ok ($BN_WS)"
