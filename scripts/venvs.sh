# Sourced by scripts/install_deps.sh and scripts/noetic_lane.sh: the pinned Python
# virtual environments under $BN_WS/venvs (docs/testing.md, "The Noetic lane").
#   make_venv NAME PYTHON REQUIREMENTS [--system-site-packages]
#     $BN_WS/venvs/NAME from PYTHON with requirements/REQUIREMENTS (pinned); done again
#     only when the interpreter or the requirements file changed (a stamp file).
#   find_python38: prints a Python 3.8 interpreter (pyenv's, else python3.8 on PATH).
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

find_python38() {
  local root candidate
  root=$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")
  for candidate in "$root"/versions/3.8.*/bin/python3.8 "$(command -v python3.8 || true)"; do
    if [ -x "$candidate" ] && "$candidate" -c 'import sys, venv; assert sys.version_info[:2] == (3, 8)' \
        2>/dev/null; then
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
