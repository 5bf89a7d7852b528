"""The real rqt host (rqt_gui, built by tools/rqt_host.sh from ../shared/thirdparty/rqt) lists the three
panels and loads each one offscreen, restoring and saving its settings, without an error."""
from __future__ import annotations

import subprocess

import pytest
from helpers import REPO_ROOT, RosProcess, wait_for

pytestmark = [pytest.mark.ros, pytest.mark.slow]

RQT_SRC = REPO_ROOT.parent / "shared" / "thirdparty" / "rqt"
PLUGINS = {"ltl_stack.gui.plugins.MappingPlugin": "ltl_stack/MappingPanel",
           "ltl_stack.gui.plugins.AnalysisPlugin": "ltl_stack/AnalysisPanel",
           "ltl_stack.gui.plugins.ControllerViewPlugin": "ltl_stack/ControllerView"}
HOST = str(REPO_ROOT / "tools" / "rqt_host.sh")
BAD = ("Traceback", "Error", "error:", "could not be loaded", "failed", "Invalid")


@pytest.fixture(scope="module")
def rqt_host():
    if not (RQT_SRC / "rqt_gui" / "package.xml").is_file():
        pytest.skip(f"the rqt sources are absent ({RQT_SRC}); see ../shared/thirdparty/README.md")
    done = subprocess.run([HOST, "build"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout.strip()


@pytest.fixture
def rqt_env(ros_master, tmp_path):
    env = dict(ros_master.env, QT_QPA_PLATFORM="offscreen", XDG_CONFIG_HOME=str(tmp_path / "config"),
               XDG_RUNTIME_DIR=str(tmp_path))
    return env


def test_rqt_lists_the_three_panels(rqt_host, rqt_env):
    done = subprocess.run([HOST, "run", "rosrun", "rqt_gui", "rqt_gui", "--list-plugins"], env=rqt_env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    listed = set(done.stdout.split())
    assert set(PLUGINS) <= listed, done.stdout + done.stderr


@pytest.mark.parametrize("plugin", sorted(PLUGINS))
def test_rqt_loads_each_panel_offscreen(rqt_host, rqt_env, ros_master, tmp_path, plugin):
    proc = RosProcess([HOST, "run", "rosrun", "rqt_gui", "rqt_gui", "-s", plugin, "--force-discover", "-v"],
                      rqt_env, tmp_path / "rqt_gui.log")
    ros_master.processes.append(proc)  # stopped with the master, even when the test fails
    try:
        proc.wait_output(f"_load_plugin({PLUGINS[plugin]}#0) successful", timeout=180)
        proc.wait_output("PluginHandler.emit_restore_settings_completed()", timeout=60)
    finally:
        proc.stop(timeout=30)  # SIGINT: rqt closes its window, saving the plugin's settings
    wait_for(lambda: not proc.running(), 90, "rqt_gui to exit")
    out = proc.output()
    assert "PluginHandler.save_settings()" in out, out[-3000:]
    lines = [line for line in out.splitlines() if any(b in line for b in BAD)]
    assert lines == [], out[-4000:]


def test_rqt_host_help_exits_0_without_building():
    done = subprocess.run([HOST, "--help"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "tools/rqt_host.sh run CMD" in done.stdout and "rqt-ws" in done.stdout


def test_a_running_rqt_never_blocks_a_second_run(rqt_host, rqt_env):
    first = subprocess.Popen([HOST, "run", "sleep", "600"], env=rqt_env, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        wait_for(lambda: first.poll() is None and _running_sleep(first.pid), 120, "the first run's command")
        second = subprocess.run([HOST, "run", "python", "-c", "print('second run')"], env=rqt_env,
                                capture_output=True, text=True, timeout=300)
        assert second.returncode == 0 and "second run" in second.stdout, second.stdout + second.stderr
        assert first.poll() is None  # the first is still running: it did not have to end first
    finally:
        first.kill()
        first.wait(60)


def _running_sleep(pid: int) -> bool:
    """True once the first run has exec'd its command (``sleep``), i.e. after its build step."""
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            return f.read().split(b"\0")[0].endswith(b"sleep")
    except OSError:
        return False


def test_run_uses_this_clones_ltl_stack(rqt_host, rqt_env):
    """The overlay is shared by the clones on a machine and chains to the workspace it was built against;
    ``run`` must still import this clone's code (it imported another clone's: its screenshots too)."""
    done = subprocess.run([HOST, "run", "python", "-c", "import ltl_stack.gui, os; print(os.path.realpath("
                           "ltl_stack.gui.__file__))"], env=rqt_env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().startswith(str(REPO_ROOT.resolve())), done.stdout
