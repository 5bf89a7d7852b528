#!/usr/bin/env bash
# The ROS-free unit suite under the other Pythons people run ROS 1 on (docs/python_versions.md):
# ./tools/test runs it after the main suite. For each version in LTL_STACK_PYTHONS (default
# "3.8 3.10 3.12 3.13"): pyenv's newest interpreter of that version (else pythonX.Y on PATH; absent: a
# clear "skipped" line), a venv of its own in $LTL_STACK_HOME/py<version> with requirements.txt's PyPI
# packages (made once per requirements; kept under a lock, so concurrent runs wait instead of building
# twice), then pytest on test/unit without ROS: the Qt panels and the tests that run the ROS node
# scripts need Debian's Python 3.11 modules and stay in the main run. Then the Noetic leg (unless
# LTL_STACK_NOETIC_LEG=0): test/integration/test_noetic_python.py runs the controller executor and a
# proposition node under 3.8 (ROS Noetic's Python) with that venv's packages first and Debian's ROS
# modules after them, on a master of its own. dd has no CUDD on 3.8, so its unit suite runs the
# Hypothesis profile suite_pure_python_dd (fewer examples) and skips the tests marked heavy_game or
# listed in test/pure_python_dd_heavy.txt (test/conftest.py; docs/python_versions.md). Exit status:
# the first failing leg's pytest code.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
ROOT=$PWD
HOME_DIR=${LTL_STACK_HOME:-$HOME/.cache/ltl_stack}
VERSIONS=${LTL_STACK_PYTHONS-3.8 3.10 3.12 3.13}
# the Python of ROS Noetic (Ubuntu 20.04): its leg runs our nodes on a real master
NOETIC=3.8
LEGS=$VERSIONS
case " $VERSIONS " in
  *" $NOETIC "*) ;;
  *) [ "${LTL_STACK_NOETIC_LEG:-1}" = 0 ] || LEGS="$LEGS $NOETIC" ;;
esac

say() { echo "[python-matrix] $*" >&2; }

# requirements.txt (its environment markers pick the versions for each Python) without the main run's
# tools (ruff, pytest-qt)
requirements() {
  grep -v -E '^(ruff|pytest-qt)==' "$ROOT/requirements.txt"
}

interpreter() {  # interpreter VERSION: the newest pyenv X.Y.Z, else pythonX.Y on PATH
  local root found=""
  root=$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")
  for candidate in "$root"/versions/"$1".*/bin/python; do
    [ -x "$candidate" ] && found=$candidate
  done
  [ -n "$found" ] || found=$(command -v "python$1" || true)
  echo "$found"
}

# Tests that run our ROS node scripts (they import rospy, Debian's Python 3.11 package).
NEEDS_ROS=(
  --ignore=test/unit/gui
  --ignore=test/unit/analysis/test_analysis_bad_input_script.py
  --deselect=test/unit/ros_nodes/test_proposition_node_logic.py::test_node_cli_json_prints_the_parameters_and_exits
  --deselect=test/unit/ros_nodes/test_proposition_node_logic.py::test_node_cli_without_options_returns_so_the_node_runs
  --deselect=test/unit/transfer/test_transfer_cli.py::test_bad_input_through_the_real_script
  --deselect=test/unit/transfer/test_transfer_thesis_examples.py::test_choose_by_distribution_prompts_through_a_pipe
  --deselect=test/unit/transfer/test_transfer_thesis_examples.py::test_choose_by_distribution_with_a_given_answer_and_without_one
  --deselect=test/unit/transfer/test_transfer_thesis_examples.py::test_example_4_through_the_real_script_with_the_shared_files
)

status=0
for version in $LEGS; do
  python=$(interpreter "$version")
  if [ -z "$python" ]; then
    say "Python $version: not installed, skipped (pyenv install $version, or put python$version on PATH)"
    continue
  fi
  venv="$HOME_DIR/py$version"
  wanted="$("$python" --version 2>&1) $(requirements | sha256sum | cut -c1-16)"
  mkdir -p "$HOME_DIR"
  (
    flock 9
    if [ "$(cat "$venv/.ltl_stack_stamp" 2>/dev/null)" != "$wanted" ]; then
      say "Python $version: making $venv (PyPI packages of requirements.txt; once)"
      rm -rf "$venv"
      "$python" -m venv "$venv"
      requirements > "$HOME_DIR/py$version-requirements.txt"
      if ! "$venv/bin/python" -m pip install -q --disable-pip-version-check \
             -r "$HOME_DIR/py$version-requirements.txt" > "$HOME_DIR/py$version-pip.log" 2>&1; then
        tail -n 20 "$HOME_DIR/py$version-pip.log" >&2
        say "Python $version: pip install failed; the whole log is in $HOME_DIR/py$version-pip.log"
        exit 3
      fi
      echo "$wanted" > "$venv/.ltl_stack_stamp"
    fi
  ) 9> "$HOME_DIR/py$version.lock" || { [ "$status" -ne 0 ] || status=3; continue; }
  code=0
  case " $VERSIONS " in
    *" $version "*)
      say "Python $version ($("$venv/bin/python" --version 2>&1)): ROS-free unit suite"
      [ "$version" != "$NOETIC" ] || say "Python $version: dd without CUDD (pure-Python dd.autoref): Hypothesis" \
        "profile suite_pure_python_dd (fewer examples); the tests marked heavy_game or listed in" \
        "test/pure_python_dd_heavy.txt are skipped (test/conftest.py)"
      # pytest-timeout is a hang guard (pytest.ini: 600 s a test); without CUDD (3.8: dd.autoref) a
      # test that kept under 5 s of CPU there may still take minutes of a loaded machine's wall time
      timeout=600
      [ "$version" != "$NOETIC" ] || timeout=1200
      # no ROS environment and no catkin workspace: the package from src/, nothing from Debian's 3.11
      set +e
      env -i HOME="$HOME" PATH="$venv/bin:/usr/bin:/bin" PYTHONPATH="$ROOT/src" LANG=C.UTF-8 \
        "$venv/bin/python" -m pytest -q -p no:cacheprovider -n "${LTL_STACK_MATRIX_WORKERS:-2}" \
        --timeout "$timeout" test/unit "${NEEDS_ROS[@]}"
      code=$?
      set -e
      ;;
  esac
  if [ "$code" -ne 0 ] && [ "$status" -eq 0 ]; then
    status=$code
  fi
  if [ "$version" = "$NOETIC" ] && [ "${LTL_STACK_NOETIC_LEG:-1}" != 0 ]; then
    say "Python $version: the executor and a proposition node on a real master (Debian's ROS modules after the venv's)"
    # the main Python runs pytest and the master; the nodes run on this venv (LTL_STACK_NOETIC_VENV)
    set +e
    LTL_STACK_NOETIC_VENV="$venv" bash -c 'source tools/env.sh > /dev/null && exec python -m pytest -q \
      -p no:cacheprovider -n 0 test/integration/test_noetic_python.py'
    code=$?
    set -e
  fi
  if [ "$code" -ne 0 ] && [ "$status" -eq 0 ]; then
    status=$code
  fi
done
exit "$status"
