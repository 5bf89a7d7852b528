"""Negotiation among more than two real ``controller_executor`` nodes on a real master (docs/negotiation.md,
"Many robots"): two robots that need one responder's gates at the same step, and a three-robot cycle.
Every promise made ends in the spec the robot runs, in its characterized-spec file and in its output."""
from __future__ import annotations

import json

import pytest
from helpers import wait_for

from ltl_stack.spec import load_spec

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def needs(me: str, peer: str, mine: str, theirs: str, out: str, also: str = "") -> tuple[str, str]:
    """A robot whose input ``mine`` is ``peer``'s output ``theirs``: it assumes it always holds and
    needs it infinitely often (so characterization alone cannot help). ``also``: more YAML peers."""
    spec = (f"[INPUT]\n{mine}\n\n[OUTPUT]\n{out}\n\n[SYS_INIT]\n!{out}\n\n[ENV_TRANS]\n{mine}'\n\n"
            f"[SYS_LIVENESS]\n{mine}\n")
    mapping = (f"negotiation:\n  robot: {me}\n  peers:\n    {peer}: {{eap: {{{mine}: {theirs}}}}}\n{also}"
               f"inputs:\n  {mine}: {{node: /t/{peer}/controller_executor, node_publish_topic: /t/{peer}/outputs/"
               f"{theirs}}}\n")
    return spec, mapping


def start(ros_master, tmp_path, robots: dict[str, tuple[str, str]]):
    procs = {}
    for robot, (spec, mapping) in robots.items():
        (tmp_path / f"{robot}.structuredslugs").write_text(spec)
        (tmp_path / f"{robot}.yaml").write_text(mapping)
    for robot in robots:
        procs[robot] = ros_master.run(
            ["rosrun", "ltl_stack", "controller_executor", str(tmp_path / f"{robot}.structuredslugs"),
             str(tmp_path / f"{robot}.yaml"), "--characterized-spec", str(tmp_path / f"{robot}.out.structuredslugs"),
             "--json", "--violation-grace", "0", "--negotiation-timeout", "20", f"__ns:=/t/{robot}"], name=robot)
    return procs


def reports(proc) -> list[str]:
    return [x for x in proc.output().splitlines() if ": negotiation " in x and " with " in x and "starting" not in x]


def states(proc) -> list[dict]:
    return [json.loads(x) for x in proc.output().splitlines() if x.startswith("{") and '"outputs"' in x]


def outputs_true(proc, *names: str) -> bool:
    return any(all(s["outputs"].get(n) for n in names) for s in states(proc))


def promises(path) -> set[str]:
    return {" ".join(c.text.split()) for c in load_spec(path).sys_safety}


def test_two_initiators_at_one_responder_keep_both_gates_open(ros_master, tmp_path):
    r1 = needs("R1", "S", "g1_S", "g1", "a")
    r2 = needs("R2", "S", "g2_S", "g2", "b")
    s_spec = "[INPUT]\na_R1\nb_R2\n\n[OUTPUT]\ng1\ng2\n\n[SYS_INIT]\n!g1 & !g2\n"
    s_map = ("negotiation:\n  robot: S\n  peers:\n    R1: {shares: {g1: g1_S}}\n    R2: {shares: {g2: g2_S}}\n"
             "inputs:\n  a_R1: {node: /t/R1/controller_executor, node_publish_topic: /t/R1/outputs/a}\n"
             "  b_R2: {node: /t/R2/controller_executor, node_publish_topic: /t/R2/outputs/b}\n")
    procs = start(ros_master, tmp_path, {"S": (s_spec, s_map), "R1": r1, "R2": r2})
    try:
        wait_for(lambda: len(reports(procs["S"])) >= 2 and reports(procs["R1"]) and reports(procs["R2"]), 120,
                 "both negotiations on both sides")
        wait_for(lambda: outputs_true(procs["S"], "g1", "g2"), 60, "S with both gates open")
    except AssertionError as err:
        raise AssertionError(f"{err}\n" + "\n".join(p.output()[-3000:] for p in procs.values())) from None
    for robot in ("S", "R1", "R2"):
        assert all("4.8.1" in line for line in reports(procs[robot])), (robot, reports(procs[robot]))
    assert {"g1'", "g2'"} <= promises(tmp_path / "S.out.structuredslugs")
    for robot in ("R1", "R2"):
        assert "waiting for the user" not in procs[robot].output(), procs[robot].output()[-3000:]
    # the gates stay open: S's latest state has both
    wait_for(lambda: all(states(procs["S"])[-1]["outputs"][g] for g in ("g1", "g2")), 60, "both gates open now")
    assert "Traceback" not in "".join(p.output() for p in procs.values())


def test_a_three_robot_cycle_keeps_every_promise(ros_master, tmp_path):
    """A needs B's x, B needs C's y, C needs A's z, all from the first step."""
    robots = {
        "A": needs("A", "B", "x_B", "x", "z", "    C: {shares: {z: z_A}}\n"),
        "B": needs("B", "C", "y_C", "y", "x", "    A: {shares: {x: x_B}}\n"),
        "C": needs("C", "A", "z_A", "z", "y", "    B: {shares: {y: y_C}}\n"),
    }
    procs = start(ros_master, tmp_path, robots)
    try:
        wait_for(lambda: all(len(reports(p)) >= 2 for p in procs.values()), 180, "two reports on every robot")
        for robot, out in (("A", "z"), ("B", "x"), ("C", "y")):
            wait_for(lambda p=procs[robot], o=out: outputs_true(p, o), 60, f"{robot}'s {out} on")
    except AssertionError as err:
        raise AssertionError(f"{err}\n" + "\n".join(p.output()[-3000:] for p in procs.values())) from None
    for robot, promise in (("A", "z'"), ("B", "x'"), ("C", "y'")):
        assert all("4.8.1" in line for line in reports(procs[robot])), (robot, reports(procs[robot]))
        assert promise in promises(tmp_path / f"{robot}.out.structuredslugs"), robot
        assert "waiting for the user" not in procs[robot].output(), procs[robot].output()[-3000:]
    assert "Traceback" not in "".join(p.output() for p in procs.values())
