"""analyze_graph on a real ROS master with real nodes: the thesis' Figs. 3.6-3.9.

Clean and patrol (Example 8): every node of test/data/analysis/clean_and_patrol.yaml runs as a real
rospy node (topics, actionlib clients and servers) under the names of the shared mapping.
The same setup with ltl_stack's own proposition nodes (action_proposition, set_velocity,
topic_threshold_sensor) and simulated robot and servers, launched as
test/data/analysis/clean_and_patrol_sim_mapping.yaml says.
Figs. 3.13-3.15 (Example 9, spheros) are checked live on the launched scenario in
test_analysis_scenarios.py, and on the thesis' own spheros mapping offline in
test/unit/analysis/test_analysis_checks.py.
"""
from __future__ import annotations

import json
import re
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
import yaml
from helpers import RosMaster, closed_port, require_shared, run_script, wait_for

from ltl_stack.analysis.checks import analyze
from ltl_stack.analysis.graph import ComputationGraph
from ltl_stack.analysis.snapshot import SnapshotError
from ltl_stack.errors import Exit
from ltl_stack.ros.graph_snapshot import take_snapshot
from ltl_stack.runtime.config.mapping import load_mapping

pytestmark = pytest.mark.ros

DATA = Path(__file__).resolve().parents[1] / "data" / "analysis"
sys.path.insert(0, str(DATA))
import scenario_graph  # noqa: E402

MGMB = "/move_group_and_move_base"


def registrations(master: RosMaster) -> set[tuple[str, str, str]]:
    pubs, subs, _ = master.system_state()
    return {("pub", t, n) for t, ns in pubs for n in ns} | {("sub", t, n) for t, ns in subs for n in ns}


def wait_until_registered(master: RosMaster, expected: set, timeout: float = 60.0) -> None:
    try:
        wait_for(lambda: expected <= registrations(master), timeout, "every scenario node to register")
    except AssertionError:
        missing = sorted(expected - registrations(master))[:10]
        logs = "\n".join(p.output()[-300:] for p in master.processes if not p.running())
        raise AssertionError(f"not registered after {timeout} s: {missing}\n{logs}") from None


@contextmanager
def scenario_on_a_master(tmp_path_factory, name: str) -> Iterator[RosMaster]:
    """A master of its own with every node of test/data/analysis/<name>.yaml running and registered."""
    master = RosMaster(tmp_path_factory.mktemp(name))
    try:
        scenario = DATA / f"{name}.yaml"
        for node in scenario_graph.load_scenario(scenario)["nodes"]:
            master.run([sys.executable, str(DATA / "scenario_graph.py"), str(scenario), node],
                       name=node.strip("/").replace("/", "_"))
        wait_until_registered(master, scenario_graph.expected_registrations(scenario))
        yield master
    finally:
        master.shutdown()


@pytest.fixture(scope="module")
def clean_and_patrol(tmp_path_factory):
    mapping = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.yaml")
    with scenario_on_a_master(tmp_path_factory, "clean_and_patrol") as master:
        yield master, mapping


def test_live_snapshot_is_the_graph_the_nodes_registered(clean_and_patrol):
    master, _ = clean_and_patrol
    live = take_snapshot(master.uri)
    expected = scenario_graph.scenario_snapshot(DATA / "clean_and_patrol.yaml")
    assert live.master == master.uri and live.taken
    assert live.nodes == expected.nodes
    assert {k: (t.type, t.publishers, t.subscribers) for k, t in live.topics.items()} == \
        {k: (t.type, t.publishers, t.subscribers) for k, t in expected.topics.items()}
    assert set(live.services) >= set(expected.services)


def test_live_clean_and_patrol_reproduces_figs_3_6_to_3_8(clean_and_patrol):
    master, mapping_path = clean_and_patrol
    mapping = load_mapping(mapping_path)
    a = analyze(ComputationGraph(take_snapshot(master.uri)), mapping, list(mapping.inputs), list(mapping.outputs))
    assert a.e1 == []  # Fig. 3.6's pairs are the actions' completion feedback, shown apart
    assert [(f.output, f.input, f.witness.text) for f in a.feedback] == [
        ("pickup", "pickup_ac", f"(/pickup) -> [{MGMB}/outputs/pickup_status] -> (/pickup_ac)"),
        ("drop", "drop_ac", f"(/drop) -> [{MGMB}/outputs/drop_status] -> (/drop_ac)")]
    groups = {g.channel: set(g.outputs) for g in a.e2}
    regions = {"rightLane", "leftLane", "topLane", "leftGround", "bottomLane", "rightGround"}
    assert groups["/cmd_vel"] == regions | {"stop", "pickup"}
    assert groups["arm_1/arm_controller/follow_joint_trajectory/action_topics"] == {"pickup", "drop"}
    assert groups["move_base/action_topics"] == regions
    assert a.e3 == [] and "/rosout" in a.graph.ignored


def run_cli(master: RosMaster, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return run_script(["rosrun", "ltl_stack", "analyze_graph", *args], env=master.env, capture_output=True,
                          text=True, timeout=timeout)


def test_cli_live_with_a_wrong_mapping_reports_e3_and_saves_the_snapshot(clean_and_patrol, tmp_path):
    master, mapping_path = clean_and_patrol
    data = yaml.safe_load(mapping_path.read_text())
    data["outputs"]["pickup"] = [data["outputs"]["pickup"],
                                 dict(data["outputs"]["drop"], node_subscribe_topic=f"{MGMB}/outputs/pickup")]
    wrong = tmp_path / "wrong.yaml"
    wrong.write_text(yaml.safe_dump(data))
    saved = tmp_path / "graph.yaml"
    spec = mapping_path.with_suffix(".slugsin")
    done = run_cli(master, "--spec", str(spec), "--mapping", str(wrong), "--live", "--json",
                   "--save-snapshot", str(saved))
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    gripper = [f for f in report["E3"] if f["topic"] == "/arm_1/gripper_controller/position_command"]
    assert [(f["output"], f["nodes"]) for f in gripper] == [("pickup", ["/pickup", "/drop"])]  # Fig. 3.9
    assert "analyze_graph: taking a snapshot of the ROS master" in done.stderr
    assert "analyze_graph: snapshot written to " + str(saved) in done.stderr
    # the saved snapshot gives the same report offline
    offline = run_cli(master, "--spec", str(spec), "--mapping", str(wrong), "--snapshot", str(saved), "--json")
    assert offline.returncode == 0, offline.stderr
    assert json.loads(offline.stdout)["E3"] == report["E3"]


# --- ltl_stack's own proposition nodes and simulated robots, launched as a mapping says ------------

def mapping_commands(mapping_path: Path) -> tuple[list[list[str]], set[tuple[str, str, str]]]:
    """rosrun commands for every node entry of a mapping (filename = the ltl_stack node, parameters =
    private parameters), and the registrations that show each one is up."""
    mapping = yaml.safe_load(mapping_path.read_text())
    commands, expected = [], set()
    for kind, topic_key in (("inputs", "node_publish_topic"), ("outputs", "node_subscribe_topic")):
        for entries in (mapping.get(kind) or {}).values():
            for entry in entries if isinstance(entries, list) else [entries]:
                ns, _, name = entry["node"].rpartition("/")
                script = re.sub(r"\.py$", "", entry["filename"])
                params = [f"_{k}:={re.sub(r'[.][.][.]$', '', yaml.safe_dump(v, default_flow_style=True).strip()).strip()}"
                          if isinstance(v, dict) else f"_{k}:={v}" for k, v in (entry.get("parameters") or {}).items()]
                commands.append(["rosrun", "ltl_stack", script, f"__ns:={ns or '/'}", f"__name:={name}",
                                 f"_proposition_topic:={entry[topic_key]}", *params])
                expected.add(("pub" if kind == "inputs" else "sub", entry[topic_key], entry["node"]))
    return commands, expected


@pytest.fixture(scope="module")
def clean_and_patrol_sim(tmp_path_factory):
    mapping = DATA / "clean_and_patrol_sim_mapping.yaml"
    arm = "/arm_1/arm_controller/follow_joint_trajectory"
    master = RosMaster(tmp_path_factory.mktemp("clean_and_patrol_sim"))
    try:
        commands, expected = mapping_commands(mapping)
        commands += [["rosrun", "ltl_stack", "sim_robot", "__name:=sim_robot"],
                     ["rosrun", "ltl_stack", "sim_navigation_server", "__name:=move_base", "_action:=/move_base"],
                     ["rosrun", "ltl_stack", "sim_manipulation_server", "__name:=arm_controller", f"_actions:=[{arm}]"]]
        expected |= {("sub", "/move_base/goal", "/move_base"), ("sub", f"{arm}/goal", "/arm_controller"),
                     ("sub", "/cmd_vel", "/sim_robot"), ("pub", f"{arm}/goal", "/pickup"), ("pub", f"{arm}/goal", "/drop"),
                     ("pub", "/move_base/goal", f"{MGMB}/outputs/topLane")}
        for i, command in enumerate(commands):
            master.run(command, name=f"cp_sim_{i:02d}")
        wait_until_registered(master, expected)
        yield master, mapping
    finally:
        master.shutdown()


def test_live_sim_clean_and_patrol_figs_3_6_to_3_9(clean_and_patrol_sim, tmp_path):
    master, mapping = clean_and_patrol_sim
    spec = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.slugsin")
    done = run_cli(master, "--spec", str(spec), "--mapping", str(mapping), "--live", "--json")
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["E1"] == []
    assert [(f["output"], f["input"], f["chain"]) for f in report["expected_feedback"]] == [
        ("pickup", "pickup_ac", f"(/pickup) -> [{MGMB}/outputs/pickup_status] -> (/pickup_ac)"),
        ("drop", "drop_ac", f"(/drop) -> [{MGMB}/outputs/drop_status] -> (/drop_ac)")]  # Fig. 3.6
    groups = {g["topic"]: g for g in report["E2"]}
    regions = ["rightLane", "leftLane", "topLane", "leftGround", "bottomLane", "rightGround"]
    assert set(groups["/cmd_vel"]["outputs"]) == {*regions, "stop", "pickup"}  # Fig. 3.7
    chains = {c["proposition"]: c["chain"] for c in groups["/cmd_vel"]["chains"]}
    assert chains["topLane"] == f"({MGMB}/outputs/topLane) -> (move_base/action_topics) -> (/move_base) -> [/cmd_vel]"
    assert chains["pickup"] == "(/pickup_approach) -> [/cmd_vel]"
    assert groups["arm_1/arm_controller/follow_joint_trajectory/action_topics"]["outputs"] == ["pickup", "drop"]
    assert report["E3"] == []
    assert sorted(sorted(s["propositions"]) for s in report["suggestions"]) == [
        sorted(["pickup", "stop", *regions]), ["drop", "pickup"]]
    # the drop node wrongly mapped to pickup as well (Fig. 3.9)
    data = yaml.safe_load(mapping.read_text())
    data["outputs"]["pickup"].append(dict(data["outputs"]["drop"], node_subscribe_topic=f"{MGMB}/outputs/pickup"))
    wrong = tmp_path / "wrong.yaml"
    wrong.write_text(yaml.safe_dump(data))
    done = run_cli(master, "--spec", str(spec), "--mapping", str(wrong), "--live", "--json")
    assert done.returncode == 0, done.stderr
    e3 = json.loads(done.stdout)["E3"]
    assert sorted((f["output"], f["topic"], f["nodes"]) for f in e3) == [
        ("pickup", "/holding", ["/pickup", "/drop"]),  # downstream: the arm server's state
        ("pickup", "arm_1/arm_controller/follow_joint_trajectory/action_topics", ["/pickup", "/drop"])]


def test_unreachable_master_is_one_clear_error():
    uri = f"http://127.0.0.1:{closed_port()}/"
    with pytest.raises(SnapshotError, match=f"cannot read the graph from the ROS master at {uri}") as err:
        take_snapshot(uri, timeout=2.0)  # gives up (pytest-timeout fails a hang), however slow the machine
    assert err.value.code == Exit.NO_ROS


def test_live_fig_3_9_mapping_as_the_thesis_gui_writes_it(clean_and_patrol, tmp_path):
    """Fig. 3.9's accidental mapping written as the thesis' GUI writes it: a second 'pickup:' block
    naming the drop node. It is analysed (it was refused, exit 2)."""
    master, mapping_path = clean_and_patrol
    second = (f"  pickup:\n    node : '/drop'\n    node_subscribe_topic : '{MGMB}/outputs/pickup'\n"
              "    pkg : 'controller_executor'\n    filename : 'plan_manipulator_path.py'\n\n")
    wrong = tmp_path / "fig_3_9.yaml"
    wrong.write_text(mapping_path.read_text().replace("  drop:\n", second + "  drop:\n", 1))
    spec = require_shared("specs", "move_group_and_move_base", "move_group_and_move_base.slugsin")
    done = run_cli(master, "--spec", str(spec), "--mapping", str(wrong), "--live", "--json")
    assert done.returncode == 0, done.stderr
    e3 = {(f["output"], f["topic"]): f["nodes"] for f in json.loads(done.stdout)["E3"]}
    assert e3[("pickup", "/arm_1/gripper_controller/position_command")] == ["/pickup", "/drop"], e3


@pytest.fixture(scope="module")
def relay_and_tester(tmp_path_factory):
    with scenario_on_a_master(tmp_path_factory, "relay_and_tester") as master:
        yield master


def test_live_relay_conflict_and_second_input_publisher(relay_and_tester):
    """move and stop each feed a forwarding node that drives /cmd_vel: they compete there (E2, through
    the relay); a second publisher on the person input topic is a finding (P1)."""
    spec = Path(__file__).resolve().parents[2] / "config" / "simple" / "simple.structuredslugs"
    done = run_cli(relay_and_tester, "--spec", str(spec), "--mapping", str(DATA / "relay_and_tester_mapping.yaml"),
                   "--live", "--json")
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["relays_followed"] == ["/forward"]
    groups = {g["topic"]: g["outputs"] for g in report["E2"]}
    assert groups["/cmd_vel"] == ["move", "stop"], report["E2"]
    assert [(f["input"], f["topic"], f["other_publishers"]) for f in report["P1"]] == [
        ("person", "/relay_demo/inputs/person", ["/tester"])]
    # a relay known to merge by design is not followed
    merged = run_cli(relay_and_tester, "--spec", str(spec), "--mapping", str(DATA / "relay_and_tester_mapping.yaml"),
                     "--live", "--json", "--add-mergers", "/forward")
    assert merged.returncode == 0, merged.stderr
    assert "/cmd_vel" not in {g["topic"] for g in json.loads(merged.stdout)["E2"]}
