"""RViz starts headless (Xvfb, software GL) on each scenario's config and subscribes to what the
config names: the markers of map_markers and each robot's odometry (the config was read and its
displays loaded)."""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest
import yaml
from helpers import wait_for

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = sorted(ROOT.glob("config/*/*.rviz"))


@pytest.fixture
def display(tmp_path):
    if shutil.which("Xvfb") is None or shutil.which("rviz") is None:
        pytest.skip("Xvfb or rviz is not installed (tools/bootstrap.sh installs both)")
    read, write = os.pipe()
    xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "1024x768x24", "-nolisten", "tcp"],
                            pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    os.close(write)
    with open(read) as fd:
        number = fd.readline().strip()
    assert number.isdigit(), "Xvfb did not report its display"
    yield f":{number}"
    xvfb.terminate()
    xvfb.wait(30)


@pytest.mark.parametrize("config", CONFIGS, ids=[p.stem for p in CONFIGS])
def test_rviz_loads_the_config_headless(ros_master, display, config):
    # the GUI tests set QT_QPA_PLATFORM=offscreen in every worker's environment when collected; RViz
    # needs a real X11 window on the Xvfb display (offscreen: no GL context, it exits at once)
    ros_master.env.update(DISPLAY=display, LIBGL_ALWAYS_SOFTWARE="1", QT_QPA_PLATFORM="xcb")
    rviz = ros_master.run(["rviz", "-d", str(config)], name="rviz")
    displays = yaml.safe_load(config.read_text())["Visualization Manager"]["Displays"]
    topics = ["/" + (d.get("Marker Topic") or d["Topic"]) for d in displays
              if d["Class"] in ("rviz/MarkerArray", "rviz/Odometry")]
    assert topics, config
    def subscribed() -> bool:
        assert rviz.running(), rviz.output()  # RViz died: say why now, not after the whole wait
        return all(ros_master.subscribers(t) for t in topics)

    wait_for(subscribed, 120, f"RViz subscribed to the config's topics {topics}")
    assert rviz.running(), rviz.output()
    # Debian's rviz asks rospack for the (absent) media_export package: not about the config
    errors = [line for line in rviz.output().splitlines()
              if ("rror" in line or "failed to load" in line) and "rospack" not in line]
    assert errors == [], rviz.output()
