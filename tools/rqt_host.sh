#!/usr/bin/env bash
# The real rqt host (rqt_gui) for machines without ROS's rqt packages (Debian bookworm has none).
#
#   tools/rqt_host.sh build              build (once) and print the overlay's devel/setup.bash
#   tools/rqt_host.sh run CMD [ARGS...]  run CMD with the project's workspace and the overlay sourced,
#                                        e.g. tools/rqt_host.sh run rosrun rqt_gui rqt_gui --list-plugins
#   tools/rqt_host.sh --help             this text (exit 0)
#
# The unchanged upstream sources live in ../shared/thirdparty/rqt (override with LTL_STACK_RQT_SRC); they are
# linked, never copied, into an overlay catkin workspace $LTL_STACK_HOME/rqt-ws built with the venv's
# python. A stamp (sources' listing and sizes, the venv) makes a second run instant; a flock keeps parallel
# runs (pytest-xdist workers) from building over each other, held only while building: a running rqt never
# holds it, so a second run starts at once. Exit 0 done, 1 the build failed, 2 bad usage, 3 the sources are
# absent (otherwise CMD's own exit code).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/paths.sh"

RQT_SRC=${LTL_STACK_RQT_SRC:-$LTL_STACK_ROOT/../shared/thirdparty/rqt}
# The physical path, so that clones reaching the same sources through a link share one build.
RQT_SRC=$(cd "$RQT_SRC" 2>/dev/null && pwd -P || echo "$RQT_SRC")
RQT_WS=$LTL_STACK_HOME/rqt-ws
PACKAGES=(qt_gui qt_gui_py_common qt_dotgraph rqt_gui rqt_gui_py rqt_py_common)

say() { echo "[rqt_host] $*" >&2; }

build() {
  local p
  for p in "${PACKAGES[@]}"; do
    if [ ! -f "$RQT_SRC/$p/package.xml" ]; then
      say "the rqt sources are absent: no $RQT_SRC/$p/package.xml"
      exit 3
    fi
  done
  [ -x "$LTL_STACK_VENV/bin/python" ] || bash "$LTL_STACK_ROOT/tools/bootstrap.sh"
  mkdir -p "$LTL_STACK_HOME"
  exec 8>"$LTL_STACK_HOME/.rqt_host.lock"
  flock 8
  build_locked
  exec 8>&-  # released here: the command run next (a long-running rqt) must not hold it
}

build_locked() {
  local want
  want=$( (echo "$RQT_SRC" "$LTL_STACK_VENV"; cd "$RQT_SRC" && find "${PACKAGES[@]}" -type f -printf '%p %s\n' \
          | sort) | sha1sum | cut -c1-40)
  if [ -f "$RQT_WS/devel/setup.bash" ] && [ "$(cat "$RQT_WS/.ltl_stack_stamp" 2>/dev/null)" = "$want" ]; then
    return 0
  fi
  say "building the rqt host in $RQT_WS from $RQT_SRC"
  rm -rf "$RQT_WS"
  mkdir -p "$RQT_WS/src"
  for p in "${PACKAGES[@]}"; do
    ln -sfn "$RQT_SRC/$p" "$RQT_WS/src/$p"
  done
  (cd "$RQT_WS" && PATH="$LTL_STACK_VENV/bin:$PATH" \
     catkin_make -DPYTHON_EXECUTABLE="$LTL_STACK_VENV/bin/python" -DCATKIN_ENABLE_TESTING=OFF \
     > "$RQT_WS/catkin_make.log" 2>&1) || {
       tail -n 40 "$RQT_WS/catkin_make.log" >&2
       say "catkin_make failed; the whole log is in $RQT_WS/catkin_make.log"
       exit 1
     }
  echo "$want" > "$RQT_WS/.ltl_stack_stamp"
}

case "${1:-}" in
  build)
    build
    echo "$RQT_WS/devel/setup.bash"
    ;;
  run)
    shift
    [ $# -gt 0 ] || { say "usage: tools/rqt_host.sh run CMD [ARGS...]"; exit 2; }
    build
    [ -f "$LTL_STACK_WS/devel/setup.bash" ] || bash "$LTL_STACK_ROOT/tools/bootstrap.sh"
    # The project's workspace first, then the overlay on top of it (--extend keeps both on the paths).
    set +u
    # shellcheck disable=SC1091
    source "$LTL_STACK_WS/devel/setup.bash"
    # shellcheck disable=SC1091
    source "$RQT_WS/devel/setup.bash" --extend
    set -u
    # The overlay is shared by every clone and chains to the workspace it was first built against
    # (another clone's, with its own ltl_stack): this clone's workspace goes in front again.
    export PYTHONPATH="$LTL_STACK_WS/devel/lib/python3/dist-packages:$PYTHONPATH" \
           ROS_PACKAGE_PATH="$LTL_STACK_WS/src:$ROS_PACKAGE_PATH" \
           CMAKE_PREFIX_PATH="$LTL_STACK_WS/devel:$CMAKE_PREFIX_PATH"
    export PATH="$LTL_STACK_VENV/bin:$PATH" ROS_PYTHON_VERSION=3
    exec "$@"
    ;;
  -h|--help|help)
    sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d' | sed 's/^# \{0,1\}//'
    ;;
  *)
    say "usage: tools/rqt_host.sh build | run CMD [ARGS...] | --help"
    exit 2
    ;;
esac
