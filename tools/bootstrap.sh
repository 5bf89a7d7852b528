#!/usr/bin/env bash
# Install what ltl_stack needs on a Debian bookworm machine, idempotently:
#   1. Debian's ROS 1 packages (only the missing ones; apt runs only when something is missing),
#   2. a venv made by /usr/bin/python3 -m venv --system-site-packages with requirements.txt,
#   3. a catkin workspace whose src/ltl_stack links to this repository, built with catkin_make,
#   4. byte-compiled sources (every node and tool is a new Python process; where PYTHONDONTWRITEBYTECODE
#      is set, as on many CI machines, each would otherwise compile the package again at start-up).
# Each step is skipped when a stamp says its inputs have not changed, so a re-run takes a second.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/paths.sh"

say() { echo "[bootstrap] $*" >&2; }

APT_PACKAGES=(
  ros-core rosbash catkin
  python3-rospy python3-rosgraph python3-rostopic python3-rosnode python3-rosservice
  python3-rosmsg python3-roslaunch python3-actionlib python3-catkin-pkg python3-genpy python3-genmsg
  ros-message-generation ros-message-runtime
  ros-std-msgs ros-actionlib-msgs ros-geometry-msgs ros-sensor-msgs ros-trajectory-msgs
  ros-nav-msgs ros-diagnostic-msgs ros-std-srvs
  python3-std-msgs python3-actionlib-msgs python3-geometry-msgs python3-sensor-msgs
  python3-trajectory-msgs python3-nav-msgs python3-diagnostic-msgs python3-std-srvs
  libstd-msgs-dev libactionlib-msgs-dev libgeometry-msgs-dev libsensor-msgs-dev libtrajectory-msgs-dev
  libnav-msgs-dev libdiagnostic-msgs-dev libstd-srvs-dev
  python3-move-base-msgs ros-move-base-msgs python3-tf2-ros python3-tf2-msgs python3-rosbag
  python3-visualization-msgs ros-visualization-msgs rviz xvfb
  python3-python-qt-binding python3-pyqt5
  python3-venv python3-dev cmake make g++ graphviz
)

install_debian_packages() {
  local installed missing=()
  installed=$(dpkg-query -W -f='${db:Status-Abbrev} ${Package}\n' "${APT_PACKAGES[@]}" 2>/dev/null \
              | awk '$1 == "ii" {print $2}' || true)
  for p in "${APT_PACKAGES[@]}"; do
    grep -qx "$p" <<<"$installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  say "installing Debian packages: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
}

stamp_matches() {  # stamp_matches FILE VALUE
  [ -f "$1" ] && [ "$(cat "$1")" = "$2" ]
}

venv_wanted() {  # what the venv depends on
  cat "$LTL_STACK_ROOT/requirements.txt" /usr/bin/python3 2>/dev/null | sha1sum | cut -c1-40
}

venv_ready() {
  [ -x "$LTL_STACK_VENV/bin/python" ] && stamp_matches "$LTL_STACK_VENV/.ltl_stack_stamp" "$(venv_wanted)"
}

make_venv() {
  venv_ready && return 0
  local want
  want=$(venv_wanted)
  say "making the virtual environment $LTL_STACK_VENV"
  mkdir -p "$LTL_STACK_HOME"
  [ -x "$LTL_STACK_VENV/bin/python" ] || /usr/bin/python3 -m venv --system-site-packages "$LTL_STACK_VENV"
  "$LTL_STACK_VENV/bin/python" -m pip install -q --disable-pip-version-check \
      -r "$LTL_STACK_ROOT/requirements.txt" > "$LTL_STACK_HOME/pip.log" 2>&1 || {
        tail -n 40 "$LTL_STACK_HOME/pip.log" >&2
        say "pip install failed; the whole log is in $LTL_STACK_HOME/pip.log"
        exit 1
      }
  echo "$want" > "$LTL_STACK_VENV/.ltl_stack_stamp"
}

workspace_wanted() {  # what catkin_make's output depends on: build files, interface files, script names
  (cd "$LTL_STACK_ROOT" && cat package.xml CMakeLists.txt setup.py msg/* srv/* action/* \
     && ls scripts && echo "$LTL_STACK_VENV") | sha1sum | cut -c1-40
}

workspace_ready() {
  [ -f "$LTL_STACK_WS/devel/setup.bash" ] && stamp_matches "$LTL_STACK_WS/.ltl_stack_stamp" "$(workspace_wanted)"
}

build_workspace() {
  workspace_ready && return 0
  local want
  want=$(workspace_wanted)
  say "building the catkin workspace $LTL_STACK_WS"
  mkdir -p "$LTL_STACK_WS/src"
  ln -sfn "$LTL_STACK_ROOT" "$LTL_STACK_WS/src/ltl_stack"
  rm -f "$LTL_STACK_WS/.ltl_stack_stamp"
  (cd "$LTL_STACK_WS" && PATH="$LTL_STACK_VENV/bin:$PATH" \
     catkin_make -DPYTHON_EXECUTABLE="$LTL_STACK_VENV/bin/python" -DCATKIN_ENABLE_TESTING=OFF \
     > "$LTL_STACK_WS/catkin_make.log" 2>&1) || {
       tail -n 40 "$LTL_STACK_WS/catkin_make.log" >&2
       say "catkin_make failed; the whole log is in $LTL_STACK_WS/catkin_make.log"
       exit 1
     }
  echo "$want" > "$LTL_STACK_WS/.ltl_stack_stamp"
}

compile_sources() {
  # compileall skips files whose .pyc is up to date, and Python ignores a .pyc older than its source.
  "$LTL_STACK_VENV/bin/python" -m compileall -q -j 0 "$LTL_STACK_ROOT/src/ltl_stack" \
      "$LTL_STACK_WS/devel/lib/python3/dist-packages/ltl_stack" > /dev/null || say "byte-compiling failed (not needed)"
}

install_debian_packages
# Two shells bootstrapping at once (two terminals, parallel tests) must not build over each other.
# The lock is taken only when something is to be built: a shell whose venv and workspace are up to
# date never waits for another one's build (a second clone bootstrapping for the first time).
if ! { venv_ready && workspace_ready; }; then
  mkdir -p "$LTL_STACK_HOME"
  exec 9>"$LTL_STACK_HOME/.bootstrap.lock"
  flock -n 9 || { say "waiting for another bootstrap to finish ($LTL_STACK_HOME/.bootstrap.lock)"; flock 9; }
  make_venv
  build_workspace
fi
compile_sources
