"""Bad parameters, bad proposition names and --help, through the real node scripts and a real master.

Every node checks every parameter at start-up: a bad one ends it with one ``[FATAL]`` line naming
the parameter and exit 2 (``Exit.BAD_INPUT``), never a node that runs with it. ``--help`` prints
help and exits 0 without touching ROS.
"""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from helpers import direct_script, run_script

from ltl_stack.errors import Exit

pytestmark = pytest.mark.ros

LOCK_SPEC = Path(__file__).resolve().parents[1] / "unit" / "runtime" / "lock.slugsin"

NODES = ["controller_executor", "set_velocity", "set_color", "publish_on_edge", "topic_threshold_sensor",
         "region_sensor", "action_proposition", "sim_robot", "sim_navigation_server", "sim_manipulation_server",
         "region_localization", "move_base_region", "topic_predicate_sensor", "map_markers"]
REGIONS = Path(__file__).resolve().parents[2] / "config" / "clean_and_patrol" / "clean_and_patrol.regions"

BAD = [
    ("controller_executor", [str(LOCK_SPEC), "_settle_steps:=2.5"], "~settle_steps must be an integer"),
    ("controller_executor", [str(LOCK_SPEC), "_rate:=nan"], "~rate must be a number >= 0"),
    ("controller_executor", [str(LOCK_SPEC), "_init_props:=5"], "~init_props must be a str or dict"),
    ("controller_executor", [str(LOCK_SPEC), "_ready_timeout:=-1"], "~ready_timeout must be a number >= 0"),
    ("controller_executor", [str(LOCK_SPEC), "_namespace:=a-b"], "~namespace must be a legal ROS name"),
    ("set_velocity", ["_rate:=0"], "~rate must be a number > 0"),
    ("set_velocity", ["_vx:=inf"], "~vx must be a finite number"),
    ("set_velocity", ["_topic:=cmd-vel"], "~topic must be a legal ROS name"),
    ("set_color", ["_r:=nan"], "~r must be a finite number"),
    ("publish_on_edge", ["_topic:=stop.now"], "~topic must be a legal ROS name"),
    ("topic_threshold_sensor", ["_topic:=/x", "_type:=std_msgs/Float64", "_field:=nosuch"],
     "~field 'nosuch': std_msgs/Float64 has no field nosuch"),
    ("topic_threshold_sensor", ["_topic:=/x", "_hysteresis:=-1"], "~hysteresis must be a number >= 0"),
    ("topic_threshold_sensor", ["_topic:=/x", "_comparison:=about"], "~comparison must be one of"),
    ("topic_threshold_sensor", ["_topic:=/x", "_stale_after:=-2"], "~stale_after must be a number >= 0"),
    ("region_sensor", ["_region:=a", "_robot_location_topic:=loc", "_rate:=-1"], "~rate must be a number >= 0"),
    ("region_sensor", ["_region:=a", "_robot_location_topic:=loc", "_scale:=0"], "~scale must be a number > 0"),
    ("action_proposition", ["_action:=/pick", "_retry_delay:=nan"], "~retry_delay must be a finite number"),
    ("action_proposition", ["_action:=/pick", "_completion_topic:=a.b"], "~completion_topic must be a legal"),
    ("action_proposition", ["_action:=/pick", "_result_field:=done"], "has no field done"),
    ("sim_robot", ["_rate:=0"], "~rate must be a number > 0"),
    ("sim_robot", ["_mode:=tank"], "~mode must be one of diff, holonomic"),
    ("sim_robot", ["_time_scale:=-1"], "~time_scale must be a number > 0"),
    ("sim_navigation_server", ["_goal_tolerance:=0"], "~goal_tolerance must be a number > 0"),
    ("sim_navigation_server", ["_odom_timeout:=inf"], "~odom_timeout must be a number > 0"),
    ("sim_manipulation_server", ["_duration:=-1"], "~duration must be a number >= 0"),
    ("sim_manipulation_server", ["_feedback_rate:=0"], "~feedback_rate must be a number > 0"),
    ("sim_navigation_server", ["_action_type:=nav2/NavigateToPose"], "~action_type must be one of"),
    ("region_localization", ["_rate:=5"], "set ~regions_file (or regions_file in the node's namespace)"),
    ("region_localization", [f"_regions_file:={REGIONS}", "_hysteresis:=-0.1"], "~hysteresis must be a number >= 0"),
    ("region_localization", [f"_regions_file:={REGIONS}", "_regions:=[kitchen]"], "no region named 'kitchen'"),
    ("region_localization", [f"_regions_file:={REGIONS}", "_source:=gps"], "~source must be one of tf, topic"),
    ("move_base_region", [f"_regions_file:={REGIONS}", "_region:=kitchen"], "no region named 'kitchen'"),
    ("move_base_region", [f"_regions_file:={REGIONS}", "_region:=topLane", "_pose:=[1]"], "[x, y] or [x, y, yaw]"),
]


@pytest.mark.parametrize("node, args, fragment", BAD, ids=[f"{n}-{a[-1]}" for n, a, _ in BAD])
def test_a_bad_parameter_ends_the_node_with_one_fatal_line(ros_master, node, args, fragment):
    proc = ros_master.run(["rosrun", "ltl_stack", node, *args], name=node)
    code = proc.popen.wait(60)
    out = proc.output()
    assert code == Exit.BAD_INPUT, out
    fatal = [line for line in out.splitlines() if "[FATAL]" in line]
    assert len(fatal) == 1 and fragment in fatal[0], out
    assert "Traceback" not in out, out


@pytest.mark.parametrize("node", NODES)
def test_help_prints_and_exits_0_without_ros(node, tmp_path):
    # A master URI where nothing listens: --help must not even try to reach it.
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:9/", ROS_HOME=str(tmp_path), ROS_LOG_DIR=str(tmp_path))
    proc = subprocess.run(direct_script(["rosrun", "ltl_stack", node, "--help"], os.environ), capture_output=True, text=True, timeout=300,
                          env=env)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("usage: ") and "exit codes: 0" in proc.stdout, proc.stdout
    assert "Traceback" not in proc.stderr and not list(tmp_path.rglob("*.log")), proc.stderr


def test_propositions_that_are_not_ros_names_are_refused_naming_them(tmp_path):
    spec = tmp_path / "names.structuredslugs"
    # The synthesizer accepts these names (and bit-blasted ones such as x@0.0.3); ROS topics cannot carry them.
    spec.write_text("[INPUT]\nsee.person\n\n[OUTPUT]\nstop@now\nmove\n\n[SYS_TRANS]\nmove'\n")
    for tool in (["controller_executor", str(spec), "--check"], ["generate_launch", "-", "--spec", str(spec)]):
        if tool[0] == "generate_launch":
            mapping = tmp_path / "names.yaml"
            mapping.write_text("outputs:\n  move:\n    node: move\n")
            tool[1] = str(mapping)
        proc = subprocess.run(direct_script(["rosrun", "ltl_stack", *tool], os.environ), capture_output=True, text=True, timeout=300)
        assert proc.returncode == Exit.BAD_INPUT, proc
        assert "'see.person', 'stop@now'" in proc.stderr and "'move'" not in proc.stderr, proc.stderr
        assert proc.stderr.startswith(f"{tool[0]}: error: {spec}: "), proc.stderr
    synth = run_script(["rosrun", "ltl_stack", "synthesize", str(spec)], capture_output=True, text=True,
                           timeout=300)
    assert synth.returncode == Exit.OK, synth.stderr


def test_unrealizable_spec_exits_10_from_the_one_table(ros_master, tmp_path):
    spec = tmp_path / "never.slugsin"
    spec.write_text("[INPUT]\nx\n\n[OUTPUT]\ny\n\n[SYS_TRANS]\n& y' ! y'\n")
    check = run_script(["rosrun", "ltl_stack", "controller_executor", str(spec), "--check"],
                           capture_output=True, text=True, timeout=300)
    assert check.returncode == Exit.UNREALIZABLE, check
    assert check.stderr.count("controller_executor: error: ") == 1 and "unrealizable" in check.stderr, check.stderr
    node = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec)], name="executor")
    assert node.popen.wait(60) == Exit.UNREALIZABLE, node.output()
    assert "[FATAL]" in node.output() and "unrealizable" in node.output(), node.output()


def test_the_namespace_param_is_honoured(ros_master):
    ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(LOCK_SPEC), "_namespace:=plant/cell2"],
                   name="executor")
    ros_master.wait_for_subscriber("/plant/cell2/inputs/a", timeout=60)
    ros_master.wait_for_publisher("/plant/cell2/outputs/busy", timeout=90)
    assert ros_master.subscribers("/lock/inputs/a") == []
