# Sourced by the Makefile's scripts: a ROS environment that does not depend on
# which python3 comes first on PATH. Debian's ROS Python libraries live in
# /usr/bin/python3, so /usr/bin goes first; /opt/ros/noetic is used when present.
export PATH="/usr/bin:/bin:$PATH"
unset PYTHONHOME
# ROS setup files read unset variables: relax `set -u` while sourcing them.
_bn_nounset=$([[ $- == *u* ]] && echo 1 || true)
set +u
if [ -f /opt/ros/noetic/setup.bash ]; then
  # shellcheck disable=SC1091
  source /opt/ros/noetic/setup.bash
fi
export ROS_PYTHON_VERSION=3
export BN_WS="${BN_WS:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/.ws}"
if [ -f "$BN_WS/devel/setup.bash" ]; then
  # shellcheck disable=SC1091
  source "$BN_WS/devel/setup.bash"
fi
# Logs of roslaunch/rostest stay inside the workspace, not in ~/.ros.
export ROS_LOG_DIR="${ROS_LOG_DIR:-$BN_WS/log}"
export ROS_HOME="${ROS_HOME:-$BN_WS/ros_home}"
[ -n "$_bn_nounset" ] && set -u
unset _bn_nounset
