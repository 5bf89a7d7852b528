"""A script run without one of requirements.txt's packages says which, and how to install it, in one
line with exit status 2 (``ltl_stack.missing``); any other uncaught error keeps its traceback."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from ltl_stack import missing

ROOT = Path(__file__).resolve().parents[3]
SPEC = ROOT / "config" / "simple" / "simple.structuredslugs"


def _run_without(tmp_path: Path, module: str, *argv: str) -> subprocess.CompletedProcess:
    """``argv`` with a ``module`` on the path that fails to import as an absent package does."""
    (tmp_path / f"{module}.py").write_text(f"raise ModuleNotFoundError({f'No module named {module!r}'!r}, "
                                           f"name={module!r})\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path), str(ROOT / "src"),
                                                       os.environ.get("PYTHONPATH", "")]))
    return subprocess.run([sys.executable, *argv], capture_output=True, text=True, timeout=300, cwd=ROOT, env=env)


def test_synthesize_without_dd_is_one_line_and_exit_2(tmp_path):
    done = _run_without(tmp_path, "dd", str(ROOT / "scripts" / "synthesize"), str(SPEC))
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr, done.stderr
    line = done.stderr.strip()
    assert line.startswith("synthesize: error: "), line
    assert "'dd' is missing" in line and "pip install -r" in line and "requirements.txt" in line, line


def test_other_errors_keep_their_traceback(tmp_path):
    done = _run_without(tmp_path, "dd", "-c", "import ltl_stack; import not_a_package_of_ours")
    assert done.returncode == 1 and "Traceback" in done.stderr and "not_a_package_of_ours" in done.stderr


def test_message_names_the_pypi_package_of_an_import_name():
    assert "'PyYAML'" in missing.message("yaml")
    assert "'dd'" in missing.message("dd.autoref")
    assert missing.message("rospy") is None  # a ROS package: rosdep's business, not requirements.txt's
