"""One robot per host: the documented per-host roslaunch commands (docs/several_machines.md) of the
multi-robot scenarios together start every node of the one-host launch, each exactly once."""
from __future__ import annotations

import subprocess

import pytest
from helpers import REPO_ROOT

pytestmark = pytest.mark.ros

SPHEROS = ("sphero_wpw", "sphero_ggw", "sphero_rgw", "sphero_wpp")
ROBOT_ONLY = ["start_executor:=false", "start_shared:=false", "start_world:=false"]
HOSTS = {
    "kitchen": [["start_A:=false", "start_C:=false"],
                ["start_world:=false", "start_D:=false", "start_C:=false"],
                ["start_world:=false", "start_D:=false", "start_A:=false"]],
    "spheros": [["robots:=none"]] + [[f"robots:={robot}", *ROBOT_ONLY] for robot in SPHEROS],
    "youbots": [["robots:=none", "start_world:=false"],
                ["robots:=youbot_1", "start_executor:=false", "wait_for_controller:=true"],
                ["robots:=youbot_2", "start_executor:=false", "start_world:=false"]],
}


def nodes(scenario: str, args: list[str]) -> list[str]:
    listed = subprocess.run(["roslaunch", "--nodes", str(REPO_ROOT / "launch" / f"{scenario}.launch"), *args],
                            capture_output=True, text=True, timeout=300)
    assert listed.returncode == 0, listed.stderr
    return listed.stdout.split()


@pytest.mark.parametrize("scenario", sorted(HOSTS))
def test_the_per_host_commands_start_every_node_once(scenario):
    whole = nodes(scenario, [])
    per_host = [nodes(scenario, args) for args in HOSTS[scenario]]
    assert all(per_host), per_host  # every host has something to run
    started = [n for host in per_host for n in host]
    assert sorted(started) == sorted(whole), (per_host, whole)
    if scenario == "spheros":  # each sphero's host runs its robot and its output nodes (their deadman guards
        # the robot's own link), the controller's host the executor, the tag inputs and the tag detector
        for robot, host in zip(SPHEROS, per_host[1:]):
            assert f"/spheros/{robot}/sim_robot" in host, host
            outputs = [n for n in host if n != f"/spheros/{robot}/sim_robot"]
            assert len(outputs) == 11 and all(n.startswith(f"/spheros/{robot}_") for n in outputs), host
        assert not any(n.startswith("/spheros/sphero_") for n in per_host[0]), per_host[0]
    if scenario == "youbots":  # each youBot's host runs its own nodes (youbot_1: its camera and person detector)
        assert per_host[0] == ["/youbots/controller_executor"], per_host[0]
        assert sorted(per_host[2]) == ["/youbots/youbot_2/sim_robot", "/youbots/youbot_2_move",
                                       "/youbots/youbot_2_stop"], per_host[2]
