"""Every scenario launch file with an ``rviz`` argument names an RViz config that exists and shows
what map_markers publishes (parse level; test_rviz_headless starts RViz on them)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[3]
LAUNCHES = sorted(p for p in (ROOT / "launch").glob("*.launch") if 'name="rviz"' in p.read_text())


def rviz_config(launch: Path) -> Path:
    match = re.search(r'type="rviz" args="-d \$\(arg config\)/([\w.]+\.rviz)"', launch.read_text())
    assert match, f"{launch.name}: no rviz node with -d $(arg config)/NAME.rviz"
    config = re.search(r'<arg name="config" default="\$\(find ltl_stack\)/(config/\w+)"', launch.read_text())
    assert config, launch.name
    return ROOT / config.group(1) / match.group(1)


def test_the_scenarios_with_a_map_or_a_robot_have_an_rviz_argument():
    assert {p.stem for p in LAUNCHES} >= {"clean_and_patrol", "alice", "patrol_recycling", "simple"}


@pytest.mark.parametrize("launch", LAUNCHES, ids=[p.stem for p in LAUNCHES])
def test_rviz_config_shows_the_markers_in_the_map_frame(launch):
    config = yaml.safe_load(rviz_config(launch).read_text())
    manager = config["Visualization Manager"]
    assert manager["Global Options"]["Fixed Frame"] == "map"
    displays = {d["Class"]: d for d in manager["Displays"]}
    assert displays["rviz/MarkerArray"]["Marker Topic"] == "markers"  # map_markers' topic, relative
    assert displays["rviz/Odometry"]["Topic"] == "odom"
    assert {"rviz/TF", "rviz/Grid"} <= set(displays)
    assert manager["Views"]["Current"]["Class"] == "rviz/TopDownOrtho"
    assert 'default="false"' in re.search(r'<arg name="rviz"[^>]*>', launch.read_text()).group(0)
