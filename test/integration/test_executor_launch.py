"""generate_launch output read by the real roslaunch, and run by it against a real master."""
from __future__ import annotations

import subprocess
import textwrap

import pytest
from helpers import require_shared, run_script, wait_for
from test_executor_node import LOCK_SPEC, Probe

from ltl_stack.runtime.config.mapping import load_mapping, resolve_node_name

pytestmark = pytest.mark.ros


@pytest.mark.parametrize("scenario", ["spheros", "move_group_and_move_base"])
def test_roslaunch_reads_the_generated_file(scenario, tmp_path):
    mapping = require_shared("specs", scenario, f"{scenario}.yaml")
    launch = tmp_path / f"{scenario}.launch"
    gen = run_script(["rosrun", "ltl_stack", "generate_launch", str(mapping), "-o", str(launch)],
                         capture_output=True, text=True, timeout=300)
    assert gen.returncode == 0, gen.stderr
    listed = subprocess.run(["roslaunch", "--nodes", str(launch)], capture_output=True, text=True, timeout=300)
    assert listed.returncode == 0, listed.stderr
    m = load_mapping(mapping)
    ns = m.scenario_namespace()
    expected = {resolve_node_name(e.node, ns) for e in m.entries() if e.node and e.pkg} | {f"/{ns}/controller_executor"}
    assert set(listed.stdout.split()) == expected, listed.stdout
    params = subprocess.run(["roslaunch", "--dump-params", str(launch)], capture_output=True, text=True, timeout=300)
    assert params.returncode == 0, params.stderr
    first = m.entries()[-1]
    for key in first.parameters:
        assert f"{resolve_node_name(first.node, ns)}/{key}:" in params.stdout, (key, params.stdout)


def test_generated_launch_runs_nodes_and_executor(ros_master, tmp_path):
    spec = tmp_path / "lock.slugsin"
    spec.write_text(LOCK_SPEC)
    mapping = tmp_path / "lock.yaml"
    mapping.write_text(textwrap.dedent("""\
        inputs:
          a:
            node: 'a_sensor'
            node_publish_topic: '/lock/inputs/a'
            pkg: 'rostopic'
            type: 'rostopic'
            args: 'pub -r 5 /lock/inputs/a std_msgs/Bool true'
          lock:
            node: 'lock_sensor'
            node_publish_topic: '/lock/inputs/lock'
            pkg: 'rostopic'
            type: 'rostopic'
            args: 'pub -r 5 /lock/inputs/lock std_msgs/Bool false'
        outputs:
          out:
            node: '/lock/outputs/out'
            node_subscribe_topic: '/lock/outputs/out'
            pkg: 'ltl_stack'
            filename: 'set_velocity'
            parameters:
              publish_topic: '/robot/cmd_vel'
              vx: 0.5
          busy:
            node: 'busy'
            node_subscribe_topic: '/lock/outputs/busy'
            pkg: 'ltl_stack'
            filename: 'set_velocity'
            parameters:
              publish_topic: '/robot/cmd_vel_busy'
        """))
    launch = tmp_path / "lock.launch"
    gen = run_script(["rosrun", "ltl_stack", "generate_launch", str(mapping), "--spec", str(spec),
                          "-o", str(launch)], capture_output=True, text=True, timeout=300)
    assert gen.returncode == 0, gen.stderr
    probe = Probe(ros_master, tmp_path, ["bool:/lock/outputs/out", "bool:/lock/outputs/busy"])
    try:
        roslaunch = ros_master.run(["roslaunch", str(launch)], name="roslaunch")
        probe.wait_value("/lock/outputs/out", True, timeout=40)
        probe.wait_value("/lock/outputs/busy", False)
        # The output node is subscribed to its proposition topic (the remap) and drives its robot topic.
        wait_for(lambda: "/lock/outputs/out" in ros_master.subscribers("/lock/outputs/out"), 20,
                 "set_velocity subscribed to /lock/outputs/out")
        wait_for(lambda: "/lock/outputs/out" in ros_master.publishers("/robot/cmd_vel"), 20,
                 "set_velocity publishing /robot/cmd_vel")
        assert ros_master.publishers("/lock/inputs/a") == ["/lock/a_sensor"]
        assert "/lock/controller_executor" in ros_master.subscribers("/lock/inputs/lock")
        assert roslaunch.running(), roslaunch.output()
    finally:
        probe.stop()


def test_the_launch_stops_when_the_executor_exits(ros_master, tmp_path):
    """The executor is required: an unrealizable spec ends the whole scenario, robots included."""
    spec = tmp_path / "never.slugsin"
    spec.write_text("[INPUT]\nperson\n\n[OUTPUT]\nmove\nstop\n\n[SYS_TRANS]\n& move' ! move'\n")
    roslaunch = ros_master.run(["roslaunch", "ltl_stack", "simple.launch", f"spec:={spec}"], name="roslaunch")
    wait_for(lambda: not roslaunch.running(), 90, "roslaunch to stop after the executor exited")
    out = roslaunch.output()
    assert "unrealizable" in out and "required process" in out.lower(), out[-3000:]
    wait_for(lambda: not [n for _, ns in ros_master.system_state()[0] for n in ns if n.startswith("/simple/")], 30,
             "every node of the scenario gone")
