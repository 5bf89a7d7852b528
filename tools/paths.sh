# Where ltl_stack keeps what it builds; sourced by tools/bootstrap.sh and tools/env.sh.
# The venv and the catkin workspace live outside the repository so that rosrun's search of the
# package folder never walks into them. Override the location with LTL_STACK_HOME.
LTL_STACK_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)
LTL_STACK_HOME=${LTL_STACK_HOME:-${XDG_CACHE_HOME:-$HOME/.cache}/ltl_stack}
LTL_STACK_VENV=$LTL_STACK_HOME/venv
# One workspace per clone, so two clones never share a build.
LTL_STACK_WS=$LTL_STACK_HOME/ws-$(printf %s "$LTL_STACK_ROOT" | sha1sum | cut -c1-10)
export LTL_STACK_ROOT LTL_STACK_HOME LTL_STACK_VENV LTL_STACK_WS
