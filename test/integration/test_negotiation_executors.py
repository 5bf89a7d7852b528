"""Integrative negotiation between real ``controller_executor`` nodes on a real master (thesis §4.8):
thesis Example 13 from ``launch/kitchen.launch`` (three robots, the simulated kitchen), and two small
robots P and Q for 4.8.2 (only one can incorporate the other's specification; both keep running)
and 4.8.3 (neither can: both abort, every output false)."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import wait_for

from ltl_stack.spec import load_spec
from ltl_stack.synthesis import synthesize

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def occurrences(log: str, text: str) -> list[float]:
    """The rospy timestamps of the log lines containing ``text``."""
    return [float(line.split("[", 3)[2].split("]")[0]) for line in log.splitlines()
            if text in line and line.startswith("[")]


def when(log: str, text: str) -> float:
    return occurrences(log, text)[0]


def test_example_13_kitchen(ros_master, tmp_path):
    out = tmp_path / "specs"
    out.mkdir()
    launch = ros_master.run(["roslaunch", "ltl_stack", "kitchen.launch", f"out:={out}"], name="kitchen")
    story = [
        "kitchen_world: D receives an order for ingredients",
        "kitchen_world: D is in road",
        "/kitchen/D/controller_executor: negotiation D->A with A: 4.8.1",
        "/kitchen/A/controller_executor: negotiation D->A with D: 4.8.1",
        "kitchen_world: D is in storage",
        "kitchen_world: D delivered the ingredients to storage",
        "/kitchen/C/controller_executor: negotiation C->A with A: 4.8.1",
        "kitchen_world: A passed the ingredients to C",
        "kitchen_world: C cooked the ingredients",
    ]
    for line in story:
        launch.wait_output(line, timeout=120)
    log = launch.output()
    # each event's time from its rospy log line (the processes' lines interleave in the output)
    times = [when(log, line) for line in story]
    assert times[2:4] == sorted(times[2:4]) or times[3] <= times[2]  # D's and A's side of one negotiation
    causal = [times[0], times[1], max(times[2:4]), *times[4:]]
    assert causal == sorted(causal), log[-6000:]
    # D's way back (two moves) and A's and C's actions after the delivery run side by side, in no set order
    wait_for(lambda: [t for t in occurrences(launch.output(), "kitchen_world: D is in company") if t > times[5]],
             timeout=120, what="D back in company after the delivery")
    assert "/kitchen/A/controller_executor:   received from D: assumption of D: always, if next road_c_D or next " \
           "storage_c_D then next openDoor" in log
    assert "/kitchen/A/controller_executor:   received from C: assumption of C: always, if next ingredientArrived " \
           "then next passIngredient" in log
    assert "Traceback" not in log and "aborted" not in log, log[-6000:]
    # ownership: A's "D is in exactly one region" and "D never in the kitchen" reach D as
    # guarantees over its activations, so D's border crossings (one message per region sensor) never
    # leave it without a safe move
    log = launch.output()
    assert "no move keeps the system safety" not in log, [x for x in log.splitlines() if "no move keeps" in x]
    # A's spec after both negotiations, written atomically where ~characterized_spec says, loads and is realizable
    a_spec = out / "A.structuredslugs"
    text = a_spec.read_text()
    assert "(road_c_D' | storage_c_D') -> openDoor'" in text and "ingredientArrived' -> passIngredient'" in text
    assert synthesize(load_spec(a_spec)).realizable
    d_text = (out / "D.structuredslugs").read_text()
    assert "(road_c' | storage_c') -> openDoor_A'" in d_text and "!(cookingArea' | prepArea')" in d_text, d_text


# P needs Q to do x (assumption x_Q', goal x_Q) and has to do p infinitely often; Q assumes P never does p.
P_SPEC = "[INPUT]\nx_Q\n\n[OUTPUT]\np\n\n[SYS_INIT]\n!p\n\n[ENV_TRANS]\nx_Q'\n\n[SYS_LIVENESS]\nx_Q\np\n"
Q_SPEC = "[INPUT]\np_P\n\n[OUTPUT]\nx\n\n[ENV_INIT]\n!p_P\n\n[SYS_INIT]\n!x\n\n[ENV_TRANS]\n!p_P'\n\n[SYS_TRANS]\n{refuse}\n"
P_MAP = """negotiation:
  robot: P
  peers:
    Q: {eap: {x_Q: x}, shares: {p: p_P}}
inputs:
  x_Q: {node: /t/Q/controller_executor, node_publish_topic: /t/Q/outputs/x}
"""
Q_MAP = """negotiation:
  robot: Q
  peers:
    P: {eap: {p_P: p}, shares: {x: x_Q}}
inputs:
  p_P: {node: /t/P/controller_executor, node_publish_topic: /t/P/outputs/p}
"""


def start_pair(ros_master, tmp_path, q_refuses: bool):
    procs = {}
    for robot, spec, mapping in (("Q", Q_SPEC.format(refuse="!x'" if q_refuses else "TRUE"), Q_MAP),
                                 ("P", P_SPEC, P_MAP)):
        (tmp_path / f"{robot}.structuredslugs").write_text(spec)
        (tmp_path / f"{robot}.yaml").write_text(mapping)
        procs[robot] = ros_master.run(
            ["rosrun", "ltl_stack", "controller_executor", str(tmp_path / f"{robot}.structuredslugs"),
             str(tmp_path / f"{robot}.yaml"), "--characterized-spec", str(tmp_path / f"{robot}.out.structuredslugs"),
             "--json", "--violation-grace", "0", "--negotiation-timeout", "20", f"__ns:=/t/{robot}"], name=robot)
    return procs


def negotiations(proc) -> str:
    return "\n".join(x for x in proc.output().splitlines() if "negotiation P->Q with" in x)


def test_only_one_incorporates_4_8_2_both_keep_running(ros_master, tmp_path):
    """P cannot promise Q never to do p (its goal); Q can promise P to do x: Q adopts P's assumption,
    P resynthesizes its own spec from where it is; both run on, x is done and p too."""
    trace = ros_master.run(["rosrun", "ltl_stack", "controller_trace", "/t/Q/controller_executor/state", "--json"],
                           name="trace")
    procs = start_pair(ros_master, tmp_path, q_refuses=False)
    wait_for(lambda: negotiations(procs["P"]) and negotiations(procs["Q"]), 90, "both negotiation reports")
    # controller_trace shows the negotiation of Q (from its ~negotiations)
    line = trace.wait_output('"event": "negotiation"', timeout=60)
    event = next(json.loads(x) for x in line.splitlines() if x.startswith('{"event": "negotiation"'))
    assert event["session"] == "P->Q" and event["case"] == "ADOPTED_PEERS" and not event["initiator"]
    assert event["received"][0] == "assumption of P: always next x", event
    assert "4.8.2: the peer incorporated this robot's specification" in negotiations(procs["P"])
    assert "4.8.2: this robot incorporated the peer's specification" in negotiations(procs["Q"])
    procs["Q"].wait_output('"x": true', timeout=60)
    procs["P"].wait_output('"p": true', timeout=60)
    assert "aborted" not in procs["P"].output() + procs["Q"].output()
    assert "x'" in (tmp_path / "Q.out.structuredslugs").read_text()


def test_neither_incorporates_4_8_3_both_abort(ros_master, tmp_path):
    procs = start_pair(ros_master, tmp_path, q_refuses=True)
    wait_for(lambda: negotiations(procs["P"]) and negotiations(procs["Q"]), 90, "both negotiation reports")
    for robot in ("P", "Q"):
        assert "4.8.3: neither robot can incorporate" in negotiations(procs[robot])
        events = wait_for(lambda r=robot: [json.loads(x) for x in procs[r].output().splitlines()
                                           if x.startswith('{"event": "aborted"')], 60, f"{robot} aborted")
        assert events
        assert procs[robot].running()  # the node stays up, every output false


def test_demo_tells_the_kitchen_story(ros_master):
    """``./tools/demo --scenario kitchen --json``: the world's events and both negotiations, then the summary."""
    demo = ros_master.run([str(Path(__file__).resolve().parents[2] / "tools" / "demo"), "--scenario", "kitchen",
                           "--json", "--timeout", "150", "--master-uri", ros_master.env["ROS_MASTER_URI"]],
                          name="demo")
    demo.wait_output('"event": "summary"', timeout=180)
    events = [json.loads(x) for x in demo.output().splitlines() if x.startswith("{")]
    summary = events[-1]
    assert summary["ok"] and summary["negotiations"] == 2, demo.output()[-4000:]
    negotiations = [(e["robot"], e["session"], e["case"]) for e in events if e["event"] == "negotiation"]
    assert sorted(negotiations) == [("A", "C->A", "BOTH_ADOPT"), ("A", "D->A", "BOTH_ADOPT"),
                                    ("C", "C->A", "BOTH_ADOPT"), ("D", "D->A", "BOTH_ADOPT")], negotiations
    world = [e["text"] for e in events if e["event"] == "world"]
    assert world.index("A opens the door") > world.index(
        "D waits in road with the ingredients: the door to storage is closed (A does not open it)")
    assert "C cooked the ingredients" in world
