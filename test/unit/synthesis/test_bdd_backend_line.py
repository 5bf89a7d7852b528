"""``synthesize`` says which BDD package it runs on: ``"bdd_backend"`` in ``--json``, and without CUDD
one line that says so and where to read how to get CUDD (docs/python_versions.md); the executor's log
names the backend once (``game.backend_line``)."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from helpers import needs_cudd

from ltl_stack.synthesis import game

ROOT = Path(__file__).resolve().parents[3]
SPEC = ROOT / "config" / "simple" / "simple.structuredslugs"
# synthesize's own entry point in a process where dd.cudd cannot be imported (dd without CUDD)
WITHOUT_CUDD = "import sys; sys.modules['dd.cudd'] = None; from ltl_stack.synthesis.cli import script; script()"


def _synthesize(*args: str, cudd: bool) -> subprocess.CompletedProcess:
    code = "from ltl_stack.synthesis.cli import script; script()" if cudd else WITHOUT_CUDD
    return subprocess.run([sys.executable, "-c", code, str(SPEC), *args], capture_output=True, text=True,
                          timeout=600, cwd=ROOT)


def test_without_cudd_one_line_says_so_and_where_to_get_it():
    done = _synthesize(cudd=False)
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stderr.splitlines() if "BDD" in line]
    assert len(lines) == 1, done.stderr
    assert "dd.autoref" in lines[0] and "docs/python_versions.md" in lines[0], lines[0]
    assert done.stdout.startswith("REALIZABLE"), done.stdout


def test_json_names_the_backend_and_quiet_says_nothing_else():
    done = _synthesize("--json", "--quiet", cudd=False)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["bdd_backend"] == "autoref"
    assert done.stderr == "", done.stderr
    done = _synthesize("--json", cudd=True)
    assert json.loads(done.stdout)["bdd_backend"] == game.BACKEND


@needs_cudd  # without it: the test above
def test_with_cudd_no_note():
    done = _synthesize(cudd=True)
    assert done.returncode == 0 and "BDD" not in done.stderr, done.stderr


def test_backend_line_names_the_package_in_use():
    line = game.backend_line()
    assert ("dd.cudd" in line) == (game.BACKEND == "cudd")  # the autoref line says "no CUDD"
    assert ("docs/python_versions.md" in line) == (game.BACKEND != "cudd")
