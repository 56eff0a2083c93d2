#!/bin/bash
# Install what blind_navigation needs from Debian 12's packages, only what is
# missing (idempotent). Where ROS Noetic lives in /opt/ros/noetic, ROS itself
# comes from there and only the non-ROS libraries are installed.
set -euo pipefail

COMMON=(g++ cmake make libyaml-cpp-dev python3-yaml python3-numpy python3-matplotlib
        python3-pytest python3-psutil python3-setuptools python3-catkin-pkg)
DEBIAN_ROS=(catkin ros-message-generation ros-message-runtime ros-std-msgs ros-geometry-msgs
            ros-nav-msgs python3-nav-msgs ros-sensor-msgs ros-actionlib-msgs ros-std-srvs
            python3-std-srvs ros-rosgraph-msgs
            python3-rospy python3-actionlib python3-rostest librostest-dev python3-roslaunch
            python3-rosbag python3-tf python3-tf2-ros python3-rosmsg python3-rosservice
            python3-rostopic python3-rosnode python3-rosmaster python3-rosparam)

if [ -f /opt/ros/noetic/setup.bash ]; then
  wanted=("${COMMON[@]}")
else
  wanted=("${COMMON[@]}" "${DEBIAN_ROS[@]}")
fi

missing=()
for pkg in "${wanted[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$pkg" 2>/dev/null || true)
  [ "$status" = installed ] || missing+=("$pkg")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#wanted[@]} Debian packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
