"""The suite's own rules (test/conftest.py): a unit test that needs ROS fails, saying where it belongs."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

import ltl_stack

TEST_ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def suite(pytester, monkeypatch):
    """A copy of the suite's conftest and helpers with a unit/ and an integration/ folder."""
    package_root = str(Path(ltl_stack.__file__).resolve().parents[1])  # however this run found it
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [package_root, os.environ.get("PYTHONPATH")])))
    for name in ("conftest.py", "helpers.py"):
        shutil.copy(TEST_ROOT / name, pytester.path / name)
    (pytester.path / "unit").mkdir()
    (pytester.path / "integration").mkdir()
    return pytester


def run(suite, folder: str, body: str):
    (suite.path / folder / f"test_{folder}_case.py").write_text(body)
    return suite.runpytest_subprocess(folder, "-p", "no:cacheprovider")


def test_a_unit_test_using_the_ros_master_fixture_fails_before_a_master_starts(suite):
    result = run(suite, "unit", "def test_x(ros_master):\n    pass\n")
    result.assert_outcomes(errors=1)  # in its setup
    result.stdout.fnmatch_lines(["*a test under test/unit uses the ros_master fixture*"])


def test_a_unit_test_starting_a_master_itself_fails(suite, tmp_path):
    result = run(suite, "unit", f"from helpers import RosMaster\n\ndef test_x():\n"
                                f"    RosMaster(__import__('pathlib').Path({str(tmp_path)!r}))\n")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*a test under test/unit starts a ROS master*"])


def test_a_unit_test_cannot_rosrun_the_package(suite):
    result = run(suite, "unit", "import os\n\ndef test_x():\n    assert os.environ['ROS_PACKAGE_PATH'] == ''\n")
    result.assert_outcomes(passed=1)


def test_unit_tests_never_reach_a_default_master(suite):
    result = run(suite, "unit", "import os\n\ndef test_x():\n"
                                "    assert os.environ['ROS_MASTER_URI'].startswith('http://127.0.0.1:')\n"
                                "    assert ':11311' not in os.environ['ROS_MASTER_URI']\n")
    result.assert_outcomes(passed=1)
