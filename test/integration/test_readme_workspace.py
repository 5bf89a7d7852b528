"""The README's "Install into your catkin workspace" commands, run as written, from a copy of the repository.

The bash block of that section runs line by line in a clean shell (no ROS, catkin or venv variables,
PATH=/usr/bin:/bin, so ``python3`` is the distribution's), with three departures, each said here:

- ``<this repository>`` is a git repository made from this clone's files as they are now (tracked and
  untracked-but-not-ignored), so the test checks the working tree, not only the last commit;
- ``rosdep install`` is not run: this machine has neither rosdep nor its network sources
  (tools/bootstrap.sh installs the same packages with apt); package.xml's keys are checked elsewhere;
- ``roslaunch ltl_stack simple.launch`` runs against a master of the test's own on a free port
  (the README says "with a roscore running").

``~`` is a home kept under LTL_STACK_HOME (``readme-home``) so that ``~/ltl_venv`` and pip's cache
outlive a run: the pip line then only checks that everything is installed. ``~/catkin_ws`` is made
afresh in each run (a link to the test's temporary folder), and one run at a time uses that home (a
lock). Then ``catkin_make install`` in the same workspace, and the installed tools from a shell that
sourced only ``install/setup.bash``, without the venv on PATH: the scripts keep the venv's Python.
"""
from __future__ import annotations

import fcntl
import os
import shutil
import subprocess
from pathlib import Path

import pytest
from helpers import REPO_ROOT, WAIT, RosProcess, bootstrap_paths, wait_for

pytestmark = [pytest.mark.slow, pytest.mark.ros, pytest.mark.timeout(3600)]  # a hang guard

SECTION = "## Install into your catkin workspace"


def readme_lines() -> list[str]:
    """The commands of the section's bash block, comments and blank lines dropped."""
    text = (REPO_ROOT / "README.md").read_text()
    block = text.split(SECTION, 1)[1].split("```bash\n", 1)[1].split("```", 1)[0]
    lines = []
    for line in block.splitlines():
        command = line.split("  #", 1)[0].strip()
        if command and not command.startswith("#"):
            lines.append(command)
    return lines


def clean_env(home: Path) -> dict[str, str]:
    return {"HOME": str(home), "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8",
            "ROS_HOME": str(home / ".ros"), "ROS_LOG_DIR": str(home / ".ros" / "log")}


def copy_of_the_repository(target: Path) -> Path:
    """A git repository holding this clone's files as they are now."""
    listed = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=REPO_ROOT,
                            capture_output=True, check=True, timeout=300).stdout.decode().split("\0")
    for name in filter(None, listed):
        source = REPO_ROOT / name
        if not os.path.lexists(source):  # deleted in the work tree, not yet committed
            continue
        (target / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(source, target / name, follow_symlinks=False)
    git = {"GIT_AUTHOR_NAME": "test", "GIT_AUTHOR_EMAIL": "test@example.org", "GIT_COMMITTER_NAME": "test",
           "GIT_COMMITTER_EMAIL": "test@example.org", "GIT_CONFIG_NOSYSTEM": "1", "HOME": str(target)}
    for command in (["git", "init", "-q"], ["git", "add", "-A"], ["git", "commit", "-q", "-m", "copy"]):
        subprocess.run(command, cwd=target, env=dict(git, PATH="/usr/bin:/bin"), check=True, timeout=300)
    return target


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    """(the environment after the README's lines up to ``source devel/setup.bash``, the workspace)."""
    home = bootstrap_paths()["home"] / "readme-home"
    home.mkdir(parents=True, exist_ok=True)
    tmp = tmp_path_factory.mktemp("readme")
    origin = copy_of_the_repository(tmp / "origin")
    with open(home / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        ws = tmp / "catkin_ws"
        (ws / "src").mkdir(parents=True)
        link = home / "catkin_ws"
        if link.is_symlink():
            link.unlink()
        link.symlink_to(ws)
        script = ["set -e", "cd ~"]
        for line in readme_lines():
            if line.startswith("rosdep install"):
                continue  # not on this machine (the module's docstring)
            if line.startswith(("rosrun ", "roslaunch ")):
                break  # run by the tests below
            script.append(line.replace("<this repository>", str(origin)))
        script.append(f'env -0 > "{tmp / "env"}"')
        log = tmp / "readme.log"
        with open(log, "w") as out:
            done = subprocess.run(["bash", "-c", "\n".join(script)], env=clean_env(home), stdout=out,
                                  stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, timeout=3000)
        assert done.returncode == 0, log.read_text()[-6000:]
        env = dict(item.split("=", 1) for item in (tmp / "env").read_text().split("\0") if "=" in item)
        yield env, ws.resolve()


def test_the_readme_block_is_the_one_this_test_runs():
    words = [line.split()[0] for line in readme_lines()]
    assert words == ["cd", "rosdep", "python3", "~/ltl_venv/bin/python", "source", "catkin_make", "source",
                     "rosrun", "roslaunch"], readme_lines()
    assert "<this repository>" in readme_lines()[0]


def test_rosrun_synthesize_as_the_readme_says(workspace):
    env, ws = workspace
    line = next(c for c in readme_lines() if c.startswith("rosrun "))
    done = subprocess.run(["bash", "-c", line], env=env, cwd=ws, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-4000:]
    assert done.stdout.startswith("REALIZABLE"), done.stdout
    # the package came from this workspace, dd from the README's venv
    assert Path(env["VIRTUAL_ENV"]).name == "ltl_venv", env.get("VIRTUAL_ENV")
    assert env["CMAKE_PREFIX_PATH"].split(":")[0] == str(Path(env["HOME"]) / "catkin_ws" / "devel"), env["CMAKE_PREFIX_PATH"]


def test_roslaunch_simple_as_the_readme_says(workspace, ros_master, tmp_path):
    env, ws = workspace
    line = next(c for c in readme_lines() if c.startswith("roslaunch "))
    env = dict(env, ROS_MASTER_URI=ros_master.uri, ROS_IP="127.0.0.1", ROS_LOG_DIR=str(tmp_path / "log"),
               ROS_HOME=str(tmp_path / "ros_home"))
    launch = RosProcess(["bash", "-c", f"exec {line}"], env, tmp_path / "roslaunch.log", cwd=ws)
    ros_master.processes.append(launch)  # stopped with the master
    # the executor synthesized Example 7 and drives its outputs; the simulated robot moves
    publishers = wait_for(lambda: ros_master.publishers("/simple/outputs/move"), 10 * WAIT,
                          "the executor publishing /simple/outputs/move")
    assert "/simple/controller_executor" in publishers, publishers
    assert launch.running(), launch.output()[-4000:]


def test_the_install_space_runs_without_the_venv_on_path(workspace, tmp_path):
    env, ws = workspace
    log = tmp_path / "install.log"
    with open(log, "w") as out:
        done = subprocess.run(["bash", "-c", "catkin_make install"], env=env, cwd=ws, stdout=out,
                              stderr=subprocess.STDOUT, timeout=3000)
    assert done.returncode == 0, log.read_text()[-6000:]
    home = Path(env["HOME"])
    done = subprocess.run(["bash", "-c", f'source "{ws}/install/setup.bash" && rospack find ltl_stack && '
                           "rosrun ltl_stack synthesize $(rospack find ltl_stack)/config/simple/simple.structuredslugs"],
                          env=clean_env(home), cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-4000:]
    package, *rest = done.stdout.splitlines()
    assert Path(package) == ws / "install" / "share" / "ltl_stack", package
    assert rest and rest[0].startswith("REALIZABLE"), done.stdout
