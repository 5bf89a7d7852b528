# Source this file to use ltl_stack from your shell:   source tools/env.sh
# It bootstraps what is missing (quickly when all is there), sources the catkin workspace and
# puts the venv's python first on PATH, so `rosrun ltl_stack ...` and `roslaunch ltl_stack ...` work.
source "$(dirname "${BASH_SOURCE[0]}")/paths.sh"
# catkin's setup script reads the positional parameters ("$@") of whoever sources it, so
# `./tools/test --help` would reach it as an argument: source it from a function called without any.
_ltl_stack_source_workspace() {
  # shellcheck disable=SC1091
  source "$LTL_STACK_WS/devel/setup.bash"
}
if bash "$LTL_STACK_ROOT/tools/bootstrap.sh"; then
  _ltl_stack_source_workspace
  unset -f _ltl_stack_source_workspace
  export PATH="$LTL_STACK_VENV/bin:$PATH"
  export ROS_PYTHON_VERSION=3
else
  echo "[env] bootstrap failed; the environment was not set up" >&2
  return 1 2>/dev/null || exit 1
fi
