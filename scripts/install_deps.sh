#!/bin/bash
# Install what the Makefile's targets (build, test, demo, bench) need, only what is
# missing (idempotent): the layer's run dependencies, the test rig's (the fake
# TurtleBot, the demo and bench, the tests: package.xml's test_depends) and the
# tools (catkin_lint for make test). On Debian 12 ROS comes from Debian's packages;
# where ROS Noetic lives in /opt/ros/noetic, from the ros-noetic-* packages.
# "a|b" installs a, or b where the distribution has no a.
# Then the pinned virtual environments (scripts/venvs.sh, requirements/): tools
# (vermin, vulture) and sim (MuJoCo). Each Python lane (3.8, 3.12, 3.13) makes its own
# pyXY venv in its set-up (scripts/python_lane.sh), beside make test's rostests.
set -euo pipefail

COMMON=(g++ cmake make libyaml-cpp-dev python3-yaml python3-numpy python3-rospkg
        python3-setuptools python3-venv python3-catkin-pkg python3-docutils
        python3-matplotlib python3-psutil python3-pytest python3-hypothesis
        "catkin-lint|python3-catkin-lint")
DEBIAN_ROS=(catkin ros-message-generation ros-message-runtime
            ros-std-msgs python3-std-msgs ros-geometry-msgs python3-geometry-msgs
            ros-nav-msgs python3-nav-msgs ros-sensor-msgs python3-sensor-msgs
            ros-actionlib-msgs python3-actionlib-msgs ros-diagnostic-msgs python3-diagnostic-msgs
            python3-rospy python3-actionlib python3-diagnostic-updater python3-genpy
            python3-rosgraph python3-roslaunch
            # the test rig (rospack-tools: the rospack command)
            ros-std-srvs python3-std-srvs ros-rosgraph-msgs python3-rosgraph-msgs
            python3-rosbag python3-tf2-ros python3-roslib python3-rosnode python3-rostest
            librostest-dev python3-rosmaster python3-rosparam python3-rostopic
            python3-rosservice python3-rosmsg python3-rosunit rospack-tools)
NOETIC_ROS=(ros-noetic-catkin ros-noetic-message-generation ros-noetic-message-runtime
            ros-noetic-std-msgs ros-noetic-geometry-msgs ros-noetic-nav-msgs
            ros-noetic-sensor-msgs ros-noetic-actionlib-msgs ros-noetic-diagnostic-msgs
            ros-noetic-rospy ros-noetic-actionlib ros-noetic-diagnostic-updater
            ros-noetic-genpy ros-noetic-rosgraph ros-noetic-roslaunch
            # the test rig
            ros-noetic-std-srvs ros-noetic-rosgraph-msgs ros-noetic-rosbag ros-noetic-tf2-ros
            ros-noetic-roslib ros-noetic-rosnode ros-noetic-rostest ros-noetic-rostopic
            ros-noetic-rosservice ros-noetic-rospack ros-noetic-rosunit)

if [ -f /opt/ros/noetic/setup.bash ]; then
  wanted=("${COMMON[@]}" "${NOETIC_ROS[@]}")
else
  wanted=("${COMMON[@]}" "${DEBIAN_ROS[@]}")
fi

installed() {
  [ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null || true)" = installed ]
}

missing=()
for choice in "${wanted[@]}"; do
  found=""
  for pkg in ${choice//|/ }; do
    if installed "$pkg"; then found=1; break; fi
  done
  [ -n "$found" ] || missing+=("$choice")
done
apt_install() {
  local SUDO="" choice pkg pick install=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    SUDO="sudo"
  fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  for choice in "${missing[@]}"; do
    pick=""
    for pkg in ${choice//|/ }; do
      if [ -n "$(apt-cache policy "$pkg" 2>/dev/null | awk '/Candidate:/ && $2 != "(none)" {print $2}')" ]; then
        pick=$pkg; break
      fi
    done
    [ -n "$pick" ] || { echo "install_deps: no package for $choice in the apt sources" >&2; exit 1; }
    install+=("$pick")
  done
  echo "install_deps: installing ${install[*]}"
  $SUDO apt-get install -y -q --no-install-recommends "${install[@]}"
}

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#wanted[@]} packages present"
else
  apt_install
fi

# shellcheck source=venvs.sh
source "$(dirname "$0")/venvs.sh"
# the venvs at once (pip's downloads and unpacking wait on the disk and network more than
# on the CPU), each failure named by make_venv
jobs=()
make_venv tools /usr/bin/python3 tools.txt & jobs+=($!)
make_venv sim /usr/bin/python3 sim.txt --system-site-packages & jobs+=($!)  # the fake's physics engine (MuJoCo)
failed=0
for job in "${jobs[@]}"; do wait "$job" || failed=1; done
[ $failed -eq 0 ] || { echo "install_deps: a venv could not be made (above)" >&2; exit 1; }
