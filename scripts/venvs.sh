# Sourced by scripts/install_deps.sh and scripts/python_lane.sh: the pinned Python
# virtual environments under $BN_WS/venvs (docs/testing.md, "The Python lanes").
#   LANE_PYTHONS: the lanes' Python versions (3.8 Noetic, 3.12 ROS-O, 3.13 Debian trixie);
#     lane VERSION's venv is $BN_WS/venvs/pyXY from requirements/pyXY.txt.
#   make_venv NAME PYTHON REQUIREMENTS [--system-site-packages]
#     $BN_WS/venvs/NAME from PYTHON with requirements/REQUIREMENTS (pinned); done again
#     only when the interpreter or the requirements file changed (a stamp file).
#   find_python VERSION: prints a Python VERSION interpreter (pyenv's, else pythonVERSION
#     on PATH).
#   debian_ros_behind VENV: Debian's pure-Python ROS libraries importable in VENV,
#     after the venv's own packages (a .pth file, read last).

venvs_repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BN_WS="${BN_WS:-$venvs_repo/.ws}"

make_venv() {
  local name=$1 python=$2 reqs="$venvs_repo/requirements/$3" flag=${4:-}
  local dir="$BN_WS/venvs/$name" stamp
  stamp="$("$python" -c 'import sys; print(sys.version.split()[0], sys.executable)') $flag $(sha1sum < "$reqs")"
  if [ -f "$dir/.bn_stamp" ] && [ "$(cat "$dir/.bn_stamp")" = "$stamp" ]; then
    return 0
  fi
  echo "venvs: making $dir ($("$python" --version 2>&1), requirements/$3)"
  rm -rf "$dir"
  mkdir -p "$BN_WS/venvs"
  "$python" -m venv $flag "$dir"
  "$dir/bin/python" -m pip install -q --disable-pip-version-check -r "$reqs" > "$dir.log" 2>&1 \
    || { tail -20 "$dir.log"; echo "venvs: pip install into $dir failed (log: $dir.log)" >&2; return 1; }
  # with the system's site-packages pip check also judges Debian's packages (pygobject
  # lacks pycairo's metadata there): checked only for a venv of its own
  if [ "$flag" != --system-site-packages ]; then
    "$dir/bin/python" -m pip check -q --disable-pip-version-check >/dev/null \
      || { echo "venvs: $dir: pip check failed" >&2; return 1; }
  fi
  echo "$stamp" > "$dir/.bn_stamp"
}

LANE_PYTHONS="3.8 3.12 3.13"

find_python() {
  local version=$1 root candidate
  root=$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")
  for candidate in "$root"/versions/"$version".*/bin/python"$version" "$(command -v python"$version" || true)"; do
    if [ -x "$candidate" ] && "$candidate" -c 'import sys, venv
assert "%d.%d" % sys.version_info[:2] == sys.argv[1]' "$version" 2>/dev/null; then
      echo "$candidate"
      return 0
    fi
  done
  return 1
}

debian_ros_behind() {
  local site
  site=$("$1/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  # .pth files are read in name order, each appending to sys.path: zz_ comes last
  echo /usr/lib/python3/dist-packages > "$site/zz_debian_ros.pth"
}
