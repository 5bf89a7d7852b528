"""A live analysis of each of the project's scenarios reports the thesis' findings and nothing else.

Each scenario is roslaunched as a user would (``roslaunch ltl_stack <scenario>.launch``, simulated
robots, the controller running) on a private master, and ``analyze_graph --live --json`` runs on it:

- simple (Example 7, one robot): move and stop both command the base (E2), suggestion "move and stop
  are mutually exclusive" (thesis 3.5.2.3); nothing else.
- clean_and_patrol (Example 8): no E1 finding; Fig. 3.6's pickup -> pickup_ac and drop -> drop_ac are
  the actions' completion feedback, shown apart with the robot's navigation feedback (its motion
  seen by its own region sensors); the region propositions and stop all command the base (Fig. 3.7).
- youbots (Example 7, two youBots): E2 per robot; C1 when one robot's move node is left unmapped,
  C2 when the robot is left out of the mapping altogether (thesis 3.5.2.5/3.5.2.6).
- spheros (Example 9): move_* and turn_* compete per robot (Fig. 3.13); C1 (Fig. 3.14) with
  sphero_wpw's move_down node unmapped, C2 (Fig. 3.15) with sphero_wrb listed; ``--apply`` makes the
  moves exclusive, which is unrealizable until the inputs are assumed exclusive (Example 9).
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from helpers import RosMaster, run_script, wait_for

from ltl_stack.analysis.suggest import ENVIRONMENT, MutualExclusion, add_to_spec
from ltl_stack.runtime.config.mapping import load_mapping, resolve_node_name
from ltl_stack.spec import load_spec
from ltl_stack.synthesis import is_realizable

pytestmark = [pytest.mark.ros, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "config"
REGIONS = ["topLane", "rightLane", "bottomLane", "leftLane", "leftGround", "rightGround"]
SPHEROS = ["sphero_wpw", "sphero_ggw", "sphero_rgw", "sphero_wpp"]
MOVES = ["move_left", "move_right", "move_up", "move_down", "stop"]
TURNS = ["turn_red", "turn_yellow", "turn_green", "turn_blue", "turn_purple", "turn_white"]
SIM_SENSORS = "/collision,/diagnostics,/imu,/odom,/pose,/current_region,/camera"  # the robots' own sensors


def expected_registrations(mapping_path: Path) -> set[tuple[str, str, str]]:
    """What every mapped proposition node registers once it is up (proposition topic, robot topic,
    action goal), with the names resolved in the mapping's scenario namespace."""
    mapping = load_mapping(mapping_path)
    ns = mapping.scenario_namespace()
    expected = set()
    for kind, section in (("inputs", mapping.inputs), ("outputs", mapping.outputs)):
        for prop, entries in section.items():
            for e in entries:
                if e.node is None or not e.pkg:
                    continue
                node = resolve_node_name(e.node, ns)
                params = e.parameters or {}
                expected.add(("pub" if kind == "inputs" else "sub", f"/{ns}/{kind}/{e.topic or prop}", node))
                if "publish_topic" in params:
                    expected.add(("pub", f"/{ns}/{params['publish_topic']}", node))
                if "sensor_topic" in params:
                    expected.add(("sub", f"/{ns}/{params['sensor_topic']}", node))
                if "action" in params:
                    expected.add(("pub", f"/{ns}/{params['action']}/goal", node))
    return expected


def registrations(master: RosMaster) -> set[tuple[str, str, str]]:
    pubs, subs, _ = master.system_state()
    return {("pub", t, n) for t, ns in pubs for n in ns} | {("sub", t, n) for t, ns in subs for n in ns}


def launch(tmp_path_factory, name: str, world: set[tuple[str, str, str]]):
    """roslaunch ``<name>.launch`` on a private master; wait until every node of the mapping and of
    the simulated world has registered, and the controller publishes its state."""
    master = RosMaster(tmp_path_factory.mktemp(name))
    process = master.run(["roslaunch", "ltl_stack", f"{name}.launch"], name=name)
    ns = load_mapping(CONFIG / name / f"{name}.yaml").scenario_namespace()
    expected = expected_registrations(CONFIG / name / f"{name}.yaml") | world | {
        ("pub", f"/{ns}/controller_executor/state", f"/{ns}/controller_executor")}
    try:
        wait_for(lambda: expected <= registrations(master), 90, f"the {name} scenario to come up")
    except AssertionError:
        missing = sorted(expected - registrations(master))[:10]
        master.shutdown()
        raise AssertionError(f"not registered: {missing}\n{process.output()[-3000:]}") from None
    return master


def analyze(master: RosMaster, spec: Path, mapping: Path, *args: str, code: int = 0) -> dict:
    done = run_script(["rosrun", "ltl_stack", "analyze_graph", "--spec", str(spec), "--mapping", str(mapping),
                           "--live", "--json", *args], env=master.env, capture_output=True, text=True, timeout=300)
    assert done.returncode == code, done.stderr
    report = json.loads(done.stdout)
    assert report["missing_nodes"] == [] and report["mapping_warnings"] == [], report["mapping_warnings"]
    return report


def pairs(findings: list[dict]) -> list[tuple[str, str]]:
    return [(f["output"], f["input"]) for f in findings]


def without_nodes(mapping: Path, folder: Path, nodes: set[str]) -> Path:
    """A copy of ``mapping`` with the output entries of ``nodes`` left out (a robot left unmapped)."""
    data = yaml.safe_load(mapping.read_text())
    for prop, entries in list(data["outputs"].items()):
        kept = [e for e in entries if e["node"] not in nodes]
        assert kept, prop
        data["outputs"][prop] = kept
    out = folder / f"{mapping.stem}_partial.yaml"
    out.write_text(yaml.safe_dump(data, sort_keys=False))
    return out


# --- Example 7, one robot ---------------------------------------------------------------------------

def test_simple_reports_move_and_stop_on_the_base_and_nothing_else(tmp_path_factory):
    world = {("sub", "/simple/cmd_vel", "/simple/sim_robot"), ("pub", "/simple/camera/person_distance", "/simple/camera")}
    master = launch(tmp_path_factory, "simple", world)
    try:
        report = analyze(master, CONFIG / "simple" / "simple.structuredslugs", CONFIG / "simple" / "simple.yaml")
    finally:
        master.shutdown()
    assert report["E1"] == [] and report["expected_feedback"] == [] and report["E3"] == []
    assert report["E2"][0]["topic"] == "/simple/cmd_vel"
    assert {tuple(g["outputs"]) for g in report["E2"]} == {("move", "stop")}  # and downstream: odom, pose
    assert [c["chain"] for c in report["E2"][0]["chains"]] == ["(/simple/move) -> [/simple/cmd_vel]",
                                                               "(/simple/stop) -> [/simple/cmd_vel]"]
    assert [(s["propositions"], s["already_in_spec"]) for s in report["suggestions"]] == [(["move", "stop"], False)]
    assert report["finding_count"] == len(report["E2"])


# --- Example 8 --------------------------------------------------------------------------------------

def test_clean_and_patrol_completion_and_navigation_feedback_apart(tmp_path_factory):
    cp = "/clean_and_patrol"
    world = {("sub", f"{cp}/cmd_vel", f"{cp}/sim_robot"), ("sub", f"{cp}/move_base/goal", f"{cp}/navigation"),
             ("sub", f"{cp}/pick/goal", f"{cp}/arm"), ("sub", f"{cp}/drop/goal", f"{cp}/arm"),
             ("pub", f"{cp}/current_region", f"{cp}/sim_robot"),
             ("pub", f"{cp}/inputs/pickup_ac", f"{cp}/pickup"), ("pub", f"{cp}/inputs/drop_ac", f"{cp}/drop")}
    master = launch(tmp_path_factory, "clean_and_patrol", world)
    config = CONFIG / "clean_and_patrol"
    try:
        report = analyze(master, config / "clean_and_patrol.structuredslugs", config / "clean_and_patrol.yaml")
    finally:
        master.shutdown()
    assert report["E1"] == [] and report["E3"] == []
    feedback = {(f["output"], f["input"]): f for f in report["expected_feedback"]}
    # Fig. 3.6: each action reports its own completion (here the action node publishes it itself)
    assert feedback.pop(("pickup", "pickup_ac"))["expected"] == "action completion"
    assert feedback.pop(("drop", "drop_ac"))["expected"] == "action completion"
    # the designed navigation feedback: every motion output reaches every region sensor, through the
    # simulated base (a motion-capture system would leave this loop out of the graph); beyond the
    # thesis' activation-completion pairs, the scenario's mapping declares it (expected_feedback:)
    assert {k: f["expected"] for k, f in feedback.items()} == {
        (y, f"{r}_rc"): "region completion" if y == r else "declared in the mapping" for y in ["stop", *REGIONS]
        for r in REGIONS}
    assert feedback[("topLane", "topLane_rc")]["chain"] == (
        f"({cp}/topLane) -> (clean_and_patrol/move_base/action_topics) -> ({cp}/navigation) -> [{cp}/cmd_vel] "
        f"-> ({cp}/sim_robot) -> [{cp}/tf] -> ({cp}/localization)")
    # Fig. 3.7: the regions (through the navigation server) and stop all command the base
    assert report["E2"][0]["topic"] == f"{cp}/cmd_vel"
    assert sorted(report["E2"][0]["outputs"]) == sorted(["stop", *REGIONS])
    assert [sorted(s["propositions"]) for s in report["suggestions"]] == [sorted(["stop", *REGIONS])]
    assert report["suggestions"][0]["already_in_spec"] is True  # the region exclusion and line "stop: no region"
    assert report["finding_count"] == len(report["E2"])


# --- Example 7, two youBots -------------------------------------------------------------------------

def test_youbots_c1_and_c2_when_a_robot_is_left_unmapped(tmp_path_factory, tmp_path):
    yb = "/youbots"
    world = {("sub", f"{yb}/youbot_1/cmd_vel", f"{yb}/youbot_1/sim_robot"),
             ("sub", f"{yb}/youbot_2/cmd_vel", f"{yb}/youbot_2/sim_robot"),
             ("pub", f"{yb}/youbot_1/camera/person_distance", f"{yb}/youbot_1_camera")}
    master = launch(tmp_path_factory, "youbots", world)
    spec, mapping = CONFIG / "simple" / "simple.structuredslugs", CONFIG / "youbots" / "youbots.yaml"
    robots = ["--robots", "youbot_1,youbot_2", "--ignore-topics", SIM_SENSORS]
    try:
        full = analyze(master, spec, mapping, *robots)
        move_unmapped = analyze(master, spec, without_nodes(mapping, tmp_path, {"youbot_2_move"}), *robots)
        folder = tmp_path / "none"
        folder.mkdir()
        robot_left_out = analyze(master, spec, without_nodes(mapping, folder, {"youbot_2_move", "youbot_2_stop"}),
                                 *robots, "--fail-on-findings", code=1)
    finally:
        master.shutdown()
    # both robots mapped: move and stop compete on each robot's base, and nothing else
    assert full["E1"] == full["E3"] == full["C1"] == full["C2"] == full["expected_feedback"] == []
    assert {g["topic"] for g in full["E2"] if g["topic"].endswith("cmd_vel")} == {
        f"{yb}/youbot_1/cmd_vel", f"{yb}/youbot_2/cmd_vel"}
    assert {tuple(g["outputs"]) for g in full["E2"]} == {("move", "stop")}
    assert [s["propositions"] for s in full["suggestions"]] == [["move", "stop"]]
    # move reaches youbot_1's cmd_vel but not youbot_2's (thesis 3.5.2.5)
    assert [(f["output"], f["suffix"], f["missing"]) for f in move_unmapped["C1"]] == [
        ("move", "/cmd_vel", ["youbot_2"])]
    assert [(p["robot"], p["chain"]) for p in move_unmapped["C1"][0]["present"]] == [
        ("youbot_1", f"({yb}/youbot_1_move) -> [{yb}/youbot_1/cmd_vel]")]
    assert move_unmapped["C2"] == []
    # youbot_2 left out altogether: C2, and not repeated under C1 (thesis 3.5.2.6)
    assert [(f["robot"], f["suffixes_of_other_robots"]) for f in robot_left_out["C2"]] == [("youbot_2", ["/cmd_vel"])]
    assert robot_left_out["C1"] == []


# --- Example 9, four spheros ------------------------------------------------------------------------

def test_spheros_figs_3_13_to_3_15_and_the_apply_flow_of_example_9(tmp_path_factory, tmp_path):
    sp = "/spheros"
    world = {("sub", f"{sp}/{r}/cmd_vel", f"{sp}/{r}/sim_robot") for r in SPHEROS} | {
        ("pub", f"{sp}/tags/left_arrow", f"{sp}/tag_detector")}
    master = launch(tmp_path_factory, "spheros", world)
    spec, mapping = CONFIG / "spheros" / "spheros.slugsin", CONFIG / "spheros" / "spheros.yaml"
    ignore = ["--ignore-topics", SIM_SENSORS]
    out = tmp_path / "spheros_moves_exclusive.slugsin"
    try:
        full = analyze(master, spec, mapping, "--robots", ",".join(SPHEROS), *ignore)
        partial = analyze(master, spec, without_nodes(mapping, tmp_path, {"sphero_wpw_move_down"}),
                          "--robots", ",".join(SPHEROS), *ignore)
        five = analyze(master, spec, mapping, "--robots", ",".join([*SPHEROS, "sphero_wrb"]), *ignore,
                       "--fail-on-findings", code=1)
        applied = analyze(master, spec, mapping, "--apply", str(out), "--suggestions", "2", code=10)
    finally:
        master.shutdown()
    # all four robots mapped (Fig. 3.12): every robot's velocity and colour topics are fought over
    assert full["E1"] == full["E3"] == full["C1"] == full["C2"] == full["expected_feedback"] == []
    by_topic = {g["topic"]: g["outputs"] for g in full["E2"]}
    for r in SPHEROS:
        assert by_topic[f"{sp}/{r}/cmd_vel"] == MOVES  # Fig. 3.13
        assert by_topic[f"{sp}/{r}/set_color"] == TURNS
    assert {tuple(o) for o in by_topic.values()} == {tuple(MOVES), tuple(TURNS)}
    assert [s["propositions"] for s in full["suggestions"]] == [TURNS, MOVES]
    # Fig. 3.14: sphero_wpw's move_down node left out of the mapping
    assert [(f["output"], f["suffix"], f["missing"]) for f in partial["C1"]] == [("move_down", "/cmd_vel", ["sphero_wpw"])]
    assert [(p["robot"], p["chain"]) for p in partial["C1"][0]["present"]] == [
        (r, f"({sp}/{r}_move_down) -> [{sp}/{r}/cmd_vel]") for r in SPHEROS[1:]]
    assert partial["C2"] == []
    # Fig. 3.15: a fifth robot in the list that the mapping leaves out altogether
    assert [(f["robot"], f["suffixes_of_other_robots"]) for f in five["C2"]] == [
        ("sphero_wrb", ["/cmd_vel", "/set_color"])]
    assert five["C1"] == []
    # Example 9: the moves made exclusive -> unrealizable; the inputs that drive them, assumed
    # exclusive, make it realizable again
    apply = applied["apply"]
    assert (apply["added"], apply["realizable_before"], apply["realizable"]) == ([2], True, False)
    hint = apply["input_assumption"]
    assert hint["propositions"] == ["left_arrow", "right_arrow", "up_arrow", "down_arrow", "stop_sign"]
    assert hint["restores_realizability"] is True
    written = load_spec(out)
    assert not is_realizable(written, robotics_semantics=True)
    assumed = add_to_spec(written, [MutualExclusion(tuple(hint["propositions"]), (), ENVIRONMENT)])
    assert is_realizable(assumed, robotics_semantics=True)
