"""Every scenario launch file with an ``rviz`` argument names an RViz config that exists and shows
what map_markers publishes (parse level; test_rviz_headless starts RViz on them)."""
from __future__ import annotations

import re
from pathlib import Path
from xml.etree import ElementTree

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[3]
SCENARIOS = sorted((ROOT / "launch").glob("*.launch"))
LAUNCHES = sorted(p for p in (ROOT / "launch").glob("*.launch") if 'name="rviz"' in p.read_text())


def rviz_config(launch: Path) -> Path:
    match = re.search(r'type="rviz" args="-d \$\(arg config\)/([\w.]+\.rviz)"', launch.read_text())
    assert match, f"{launch.name}: no rviz node with -d $(arg config)/NAME.rviz"
    config = re.search(r'<arg name="config" default="\$\(find ltl_stack\)/(config/\w+)"', launch.read_text())
    assert config, launch.name
    return ROOT / config.group(1) / match.group(1)


def test_the_scenarios_with_a_map_or_a_robot_have_an_rviz_argument():
    assert {p.stem for p in LAUNCHES} >= {"clean_and_patrol", "alice", "patrol_recycling", "simple", "kitchen",
                                          "youbots", "spheros"}


def robot_namespaces(launch: Path) -> list[str]:
    """The namespaces (relative to the scenario's group) of the launch file's sim_robot nodes."""
    root = ElementTree.parse(launch).getroot()
    scenario = next(g for g in root.iter("group") if g.get("ns"))
    found = []

    def walk(element, path):
        for child in element:
            if child.tag == "group":
                walk(child, path + ([child.get("ns")] if child.get("ns") else []))
            elif child.tag == "node" and child.get("type") == "sim_robot":
                found.append(("/".join(path), child))
    walk(scenario, [])
    return found


@pytest.mark.parametrize("launch", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_several_robots_have_their_own_tf_frames(launch):
    """One robot may use odom/base_link; with several, each prefixes its frames with its namespace."""
    robots = robot_namespaces(launch)
    if len(robots) > 1:
        prefixed = {ns: {p.get("name"): p.get("value") for p in node.findall("param")}.get("prefix_frames")
                    for ns, node in robots}
        assert set(prefixed.values()) == {"true"} and len(prefixed) == len(robots), prefixed


@pytest.mark.parametrize("launch", LAUNCHES, ids=[p.stem for p in LAUNCHES])
def test_rviz_config_shows_the_markers_in_the_map_frame(launch):
    config = yaml.safe_load(rviz_config(launch).read_text())
    manager = config["Visualization Manager"]
    assert manager["Global Options"]["Fixed Frame"] == "map"
    displays = manager["Displays"]
    classes = {d["Class"] for d in displays}
    # map_markers' topics, relative: one per map_markers node of the launch file (kitchen: one per robot)
    text = launch.read_text()
    marker_nodes = re.findall(r'<group ns="(\w+)"[^>]*>\s*<node name="map_markers"', text)
    want_markers = [f"{ns}/markers" for ns in marker_nodes] or ["markers"]
    # and the static map (region_markers, latched once) of the node that draws the regions, when there is a map
    if list(rviz_config(launch).parent.glob("*.regions")):
        drawing = [ns for ns, body in re.findall(r'<group ns="(\w+)"[^>]*>\s*<node name="map_markers"(.*?)</node>', text,
                                                 re.S) if 'name="draw_regions" value="false"' not in body]
        want_markers += [f"{ns}/region_markers" for ns in drawing] or ["region_markers"]
    assert sorted(d["Marker Topic"] for d in displays if d["Class"] == "rviz/MarkerArray") == sorted(want_markers)
    # one odometry display per simulated robot, on its topic
    robots = robot_namespaces(launch)
    odom = sorted(d["Topic"] for d in displays if d["Class"] == "rviz/Odometry")
    assert odom == sorted(f"{ns}/odom" if ns else "odom" for ns, _ in robots), odom
    assert "rviz/Grid" in classes and ("rviz/TF" in classes) == bool(robots)
    assert manager["Views"]["Current"]["Class"] == "rviz/TopDownOrtho"
    assert 'default="false"' in re.search(r'<arg name="rviz"[^>]*>', launch.read_text()).group(0)
