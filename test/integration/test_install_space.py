"""The install space works on its own: ``catkin_make install``, then every tool from a shell that
sourced ``install/setup.bash`` and nothing else (no devel space, no source folder, no venv on PATH).

The install is built once per run in the workspace tools/bootstrap.sh made, in a build and devel
folder of its own (reused by later runs; ~10 s CPU the first time), so it never rewrites the devel
space the rest of the suite is using and never waits for bootstrap's lock.
"""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest
from helpers import REPO_ROOT, bootstrap_paths, closed_port

# the first test also waits for the module's catkin_make install: ~3 min at load 20, over 10 at load 30
pytestmark = [pytest.mark.slow, pytest.mark.timeout(1800)]

SCRIPTS = sorted(p.name for p in (REPO_ROOT / "scripts").iterdir() if p.is_file())


def test_scripts_folder_is_what_the_suite_checks():
    assert len(SCRIPTS) >= 20 and "synthesize" in SCRIPTS and "controller_executor" in SCRIPTS, SCRIPTS


def clean_env(tmp: Path) -> dict[str, str]:
    """No ROS, Python or catkin variables, no venv on PATH; ROS_MASTER_URI at a closed port."""
    return {"HOME": os.environ.get("HOME", "/root"), "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8",
            "ROS_MASTER_URI": f"http://127.0.0.1:{closed_port()}/", "ROS_HOME": str(tmp / "ros_home"),
            "ROS_LOG_DIR": str(tmp / "ros_log")}


@pytest.fixture(scope="module")
def install(tmp_path_factory) -> Path:
    paths = bootstrap_paths()
    assert (paths["ws"] / "devel" / "setup.bash").is_file(), f"no workspace at {paths['ws']}: run tools/bootstrap.sh"
    env = clean_env(tmp_path_factory.mktemp("build"))
    env["PATH"] = f"{paths['venv'] / 'bin'}:{env['PATH']}"
    log = paths["ws"] / "catkin_make_install.log"
    with open(log, "w") as out:
        # a build and devel folder of its own: the suite's other tests import the generated messages
        # from devel/, which catkin would rewrite (not atomically) if it saw a source newer than them
        proc = subprocess.run(["catkin_make", "install", "--build", "build_install",
                               f"-DCATKIN_DEVEL_PREFIX={paths['ws'] / 'devel_install'}",
                               f"-DCMAKE_INSTALL_PREFIX={paths['ws'] / 'install'}",
                               f"-DPYTHON_EXECUTABLE={paths['venv'] / 'bin' / 'python'}",
                               "-DCATKIN_ENABLE_TESTING=OFF"],
                              cwd=paths["ws"], env=env, stdout=out, stderr=subprocess.STDOUT, timeout=1500)
    assert proc.returncode == 0, log.read_text()[-4000:]
    return paths["ws"] / "install"


@pytest.fixture(scope="module")
def install_env(install, tmp_path_factory) -> dict[str, str]:
    """The environment of a clean shell after ``source install/setup.bash`` (sourced once: it takes a
    Python process of its own)."""
    proc = subprocess.run(["bash", "-c", f'source "{install}/setup.bash" && env -0'],
                          env=clean_env(tmp_path_factory.mktemp("install_env")), capture_output=True, text=True,
                          timeout=300, check=True)
    return dict(item.split("=", 1) for item in proc.stdout.split("\0") if "=" in item)


def installed(install_env: dict[str, str], tmp_path: Path, command: str,
              timeout: float = 120) -> subprocess.CompletedProcess:
    """``command`` in bash with ``install_env``, from an empty folder."""
    env = dict(install_env, ROS_HOME=str(tmp_path / "ros_home"), ROS_LOG_DIR=str(tmp_path / "ros_log"))
    return subprocess.run(["bash", "-c", command], env=env, cwd=tmp_path, capture_output=True, text=True,
                          timeout=timeout, stdin=subprocess.DEVNULL)


def within(path: Path, folder: Path) -> bool:
    """``path`` is ``folder`` or inside it (``Path.is_relative_to`` is Python 3.9+)."""
    return path == folder or folder in path.parents


def test_the_shell_sees_only_the_install_space(install, install_env, tmp_path):
    proc = installed(install_env, tmp_path, 'echo "$ROS_PACKAGE_PATH|$PYTHONPATH|$CMAKE_PREFIX_PATH"; rospack find ltl_stack; '
                     'python3 -c "import ltl_stack; print(ltl_stack.__file__)"')
    assert proc.returncode == 0, proc.stderr
    paths, package, module = proc.stdout.splitlines()
    for entry in paths.replace("|", ":").split(":"):
        assert not entry or within(Path(entry), install), paths
    assert Path(package) == install / "share" / "ltl_stack", package
    assert within(Path(module), install / "lib"), module


def test_every_module_of_the_package_is_installed(install):
    source = REPO_ROOT / "src" / "ltl_stack"
    target = next((install / "lib").glob("python3*/*-packages/ltl_stack"))
    wanted = {p.relative_to(source) for p in source.rglob("*.py")}
    assert wanted <= {p.relative_to(target) for p in target.rglob("*.py")}


def test_synthesize_runs_with_the_workspace_python(install_env, tmp_path):
    proc = installed(install_env, tmp_path, "rosrun ltl_stack synthesize "
                     "$(rospack find ltl_stack)/config/clean_and_patrol/clean_and_patrol.structuredslugs --json")
    assert proc.returncode == 0, proc.stderr  # was: No module named 'dd' (the first python3 on PATH ran it)
    assert json.loads(proc.stdout), proc.stdout


def test_controller_executor_checks_an_installed_scenario(install_env, tmp_path):
    proc = installed(install_env, tmp_path, "rosrun ltl_stack controller_executor --check "
                     "$(rospack find ltl_stack)/config/simple/simple.structuredslugs "
                     "$(rospack find ltl_stack)/config/simple/simple.yaml")
    assert proc.returncode == 0, proc.stderr
    assert "/simple/inputs/person" in proc.stdout + proc.stderr, proc.stdout + proc.stderr


def test_roslaunch_finds_the_installed_launch_files(install, install_env, tmp_path):
    proc = installed(install_env, tmp_path, "roslaunch --files ltl_stack clean_and_patrol.launch && "
                     "roslaunch --nodes ltl_stack simple.launch")
    assert proc.returncode == 0, proc.stderr
    files = [line for line in proc.stdout.splitlines() if line.endswith(".launch")]
    assert {Path(f).name for f in files} == {"clean_and_patrol.launch", "clean_and_patrol_propositions.launch"}
    assert all(within(Path(f), install) for f in files), files
    assert "/simple/controller_executor" in proc.stdout, proc.stdout


@pytest.mark.parametrize("script", SCRIPTS)
def test_every_installed_script_prints_its_help(install_env, tmp_path, script):
    """Exit 0 with the usage, and no node started: the master is a closed port, so a node that ignored
    --help would hang (ended by the timeout) or fail."""
    proc = installed(install_env, tmp_path, f"rosrun ltl_stack {script} --help", timeout=60)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out
    assert "usage:" in proc.stdout.lower() and "Traceback" not in out, out
