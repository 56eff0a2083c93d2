#!/bin/bash
# The simulator's physics engine (a test and bench dependency, never the product's):
# MuJoCo from PyPI, pinned, in a virtualenv that sees the system's ROS Python packages
# ($BN_WS/venvs/sim). Idempotent: fast when the pinned version is already there.
# sim/mujoco_kobuki.py finds it through $BN_WS; see docs/fake_turtlebot.md.
set -euo pipefail
MUJOCO_VERSION=3.1.6   # wheels for CPython 3.8 (Ubuntu 20.04) to 3.12 (Debian 12 has 3.11)
BN_WS="${BN_WS:-$(cd "$(dirname "$0")/.." && pwd)/.ws}"
venv="$BN_WS/venvs/sim"
if [ -x "$venv/bin/python" ] && \
   [ "$("$venv/bin/python" -c 'import mujoco; print(mujoco.__version__)' 2>/dev/null)" = "$MUJOCO_VERSION" ]; then
  echo "install_sim_venv: mujoco $MUJOCO_VERSION present ($venv)"
  exit 0
fi
mkdir -p "$BN_WS/venvs"
/usr/bin/python3 -m venv --system-site-packages "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check "mujoco==$MUJOCO_VERSION"
echo "install_sim_venv: mujoco $("$venv/bin/python" -c 'import mujoco; print(mujoco.__version__)') in $venv"
