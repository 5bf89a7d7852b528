"""Relative names: a scenario launched inside ``<group ns>`` lives entirely in it, and two copies of
one scenario run side by side on one master, each controller stepping on its own."""
from __future__ import annotations

import xmlrpc.client

import pytest
from helpers import wait_for
from test_executor_node import Probe

pytestmark = pytest.mark.ros

TWO_ROBOTS = """<launch>
  <group ns="robot1"><include file="$(find ltl_stack)/launch/simple.launch"/></group>
  <group ns="robot2"><include file="$(find ltl_stack)/launch/simple.launch"/></group>
</launch>
"""
# What a master and roslaunch always have, and the diagnostics every node reports to (by convention
# /diagnostics is global: one aggregator for the whole system).
GLOBAL_TOPICS = {"/rosout", "/rosout_agg", "/diagnostics"}
GLOBAL_PARAMS = ("/run_id", "/rosdistro", "/rosversion", "/roslaunch/")


def test_two_copies_of_the_simple_scenario_run_side_by_side(ros_master, tmp_path):
    launch = tmp_path / "two_robots.launch"
    launch.write_text(TWO_ROBOTS)
    robots = ("robot1", "robot2")
    states = {r: f"/{r}/simple/controller_executor/state" for r in robots}
    probe = Probe(ros_master, tmp_path, [f"state:{t}" for t in states.values()])
    try:
        roslaunch = ros_master.run(["roslaunch", str(launch)], name="roslaunch")

        def stepped(robot: str) -> list[dict]:
            return [e for e in probe.of("state", topic=states[robot]) if e["state"] >= 0]

        # Each scripted camera shows its person at t=3 s: each controller steps to stop on its own.
        for robot in robots:
            try:
                wait_for(lambda r=robot: [e for e in stepped(r) if e["inputs"]["person"] and e["outputs"]["stop"]],
                         90, f"{robot}'s controller to stop for the person")
            except AssertionError:
                raise AssertionError(roslaunch.output()[-4000:]) from None
        publishers, subscribers, services = ros_master.system_state()
        nodes = {n for _, ns in (*publishers, *subscribers, *services) for n in ns}
        ours = nodes - {"/rosout"} - {n for n in nodes if n.startswith("/probe")}
        assert ours and all(n.startswith(("/robot1/simple/", "/robot2/simple/")) for n in ours), sorted(ours)
        for robot in robots:
            assert {n for n in ours if n.startswith(f"/{robot}/")} == {
                f"/{robot}/simple/{n}" for n in ("sim_robot", "camera", "person", "move", "stop",
                                                 "controller_executor")}, sorted(ours)
        topics = {t for t, _ in (*publishers, *subscribers)} - GLOBAL_TOPICS
        assert all(t.startswith(("/robot1/", "/robot2/")) for t in topics), sorted(topics)
        for robot in robots:
            for topic in ("simple/inputs/person", "simple/outputs/move", "simple/outputs/stop", "simple/cmd_vel",
                          "simple/camera/person_distance", "simple/odom"):
                assert f"/{robot}/{topic}" in topics, (robot, topic, sorted(topics))
        services = {s for s, _ in services}
        assert {f"/{r}/simple/controller_executor/set_running" for r in robots} <= services, sorted(services)
        assert all(s.startswith(("/robot1/", "/robot2/", "/rosout/", "/probe")) for s in services), sorted(services)
        code, _, params = xmlrpc.client.ServerProxy(ros_master.uri).getParamNames("/pytest")
        assert code == 1
        ours_params = [p for p in params if not p.startswith(GLOBAL_PARAMS)]
        assert ours_params and all(p.startswith(("/robot1/simple/", "/robot2/simple/")) for p in ours_params), \
            sorted(ours_params)
        # Pausing robot1 leaves robot2 running.
        probe.call("/robot1/simple/controller_executor/set_running", False)
        wait_for(lambda: probe.of("state", topic=states["robot1"], running=False), 90, "robot1 paused")
        assert probe.of("state", topic=states["robot2"])[-1]["running"] is True
        assert roslaunch.running(), roslaunch.output()[-3000:]
    finally:
        probe.stop()
