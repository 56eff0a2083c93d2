#!/bin/bash
# Build the package into a fresh workspace's install space as a user does
# (`catkin_make install`), in an environment that knows only the system's ROS:
#   install_space.sh WORKSPACE
# WORKSPACE/src/blind_navigation links the repo; the output goes to WORKSPACE/build.log,
# and catkin_make's exit status to WORKSPACE/build.status, written last (a reader waits
# for it). install_space.test runs this itself, or waits for run_tests.sh's run of it
# (BN_INSTALL_SPACE: built beside the rostests, untimed).
set -u
repo=$(cd "$(dirname "$0")/.." && pwd)
ws=${1:?usage: install_space.sh WORKSPACE}
rm -rf "$ws"
mkdir -p "$ws/src"
ln -s "$repo" "$ws/src/blind_navigation"
env -i PATH=/usr/bin:/bin HOME="$HOME" LANG=C.UTF-8 ROS_PYTHON_VERSION=3 bash -c '
  [ -f /opt/ros/noetic/setup.bash ] && source /opt/ros/noetic/setup.bash
  catkin_make -C "$0" install -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=OFF \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$0/install"' "$ws" > "$ws/build.log" 2>&1
echo $? > "$ws/build.status.tmp" && mv "$ws/build.status.tmp" "$ws/build.status"
