"""The suite's own rules (test/conftest.py): a unit test that needs ROS fails, saying where it belongs."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import ltl_stack

TEST_ROOT = Path(__file__).resolve().parents[2]

CASES = {
    "test_uses_the_fixture": "def test_uses_the_fixture(ros_master):\n    pass\n",
    "test_starts_a_master": "from helpers import RosMaster\n\ndef test_starts_a_master(tmp_path):\n"
                            "    RosMaster(tmp_path)\n",
    "test_no_package_path": "import os\n\ndef test_no_package_path():\n"
                            "    assert os.environ['ROS_PACKAGE_PATH'] == ''\n",
    "test_no_default_master": "import os\n\ndef test_no_default_master():\n"
                              "    uri = os.environ['ROS_MASTER_URI']\n"
                              "    assert uri.startswith('http://127.0.0.1:') and ':11311' not in uri\n",
}


@pytest.fixture(scope="module")
def outcome(tmp_path_factory):
    """Each case as a test file of its own under unit/ of a copy of the suite's conftest and helpers,
    all run by one pytest process; gives a case's line of the report and the whole output."""
    root = tmp_path_factory.mktemp("suite")
    for name in ("conftest.py", "helpers.py", "pure_python_dd_heavy.txt"):
        shutil.copy(TEST_ROOT / name, root / name)
    (root / "unit").mkdir()
    for name, body in CASES.items():
        (root / "unit" / f"{name}.py").write_text(body)
    package_root = str(Path(ltl_stack.__file__).resolve().parents[1])  # however this run found it
    env = dict(os.environ, COLUMNS="400",
               PYTHONPATH=os.pathsep.join(filter(None, [package_root, os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, "-m", "pytest", "unit", "-p", "no:cacheprovider", "-p", "no:xdist",
                           "-rA", f"--basetemp={root / 'tmp'}"], cwd=root, env=env, capture_output=True, text=True,
                          timeout=300)
    lines = proc.stdout.splitlines()
    return lambda name: next((line for line in lines if line.startswith(("PASSED", "FAILED", "ERROR"))
                              and f"::{name}" in line), proc.stdout + proc.stderr)


def test_a_unit_test_using_the_ros_master_fixture_fails_before_a_master_starts(outcome):
    line = outcome("test_uses_the_fixture")
    assert line.startswith("ERROR") and "a test under test/unit uses the ros_master fixture" in line, line


def test_a_unit_test_starting_a_master_itself_fails(outcome):
    line = outcome("test_starts_a_master")
    assert line.startswith("FAILED") and "a test under test/unit starts a ROS master" in line, line


def test_a_unit_test_cannot_rosrun_the_package(outcome):
    assert outcome("test_no_package_path").startswith("PASSED")


def test_unit_tests_never_reach_a_default_master(outcome):
    assert outcome("test_no_default_master").startswith("PASSED")
