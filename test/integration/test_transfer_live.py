"""Code transfer against a real ROS master: A.2 listing and prompt, A.1+A.2, and running the result."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import require_shared, wait_for

from ltl_stack.errors import Exit
from ltl_stack.ros.live_channels import list_live_channels
from ltl_stack.transfer.choose import rule_choice
from ltl_stack.transfer.errors import TransferError
from ltl_stack.transfer.limits import load_limits

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]  # a hang guard, far above the waits

DATA = Path(__file__).resolve().parents[1] / "data" / "transfer"
TURTLEBOT_TWIST = ["/cmd_vel_mux/input/navi", "/cmd_vel_mux/input/safety_controller", "/cmd_vel_mux/input/switch",
                   "/cmd_vel_mux/input/teleop", "/mobile_base/commands/velocity"]
FJT = "control_msgs/FollowJointTrajectoryAction"


def live(ros_master):
    return list_live_channels(ros_master.uri)


def start_target_robot(ros_master, twist_topics, actions=()):
    ros_master.run([sys.executable, str(DATA / "target_robot_node.py"),
                    f"_twist_topics:=[{', '.join(twist_topics)}]", "_scan_topic:=/scan",
                    f"_actions:=[{', '.join(actions)}]"], name="target_robot")
    expected = set(twist_topics) | set(actions) | {"/scan"}
    wait_for(lambda: expected <= {name for name, _ in live(ros_master)}, 90, "the target robot's channels")


def transfer(ros_master, tmp_path, program, source, target, *extra, answer=""):
    args = ["rosrun", "ltl_stack", "ros_code_transfer", str(DATA / program), "--from", source, "--to", target,
            "--robots", str(require_shared("robots")), "-o", str(tmp_path / "out.py"), "--live", *extra]
    return subprocess.run(args, env=ros_master.env, input=answer, capture_output=True, text=True, timeout=300)


def test_live_listing_has_topics_with_types_and_actions(ros_master):
    start_target_robot(ros_master, TURTLEBOT_TWIST[:2], ["/arm/follow"])
    channels = live(ros_master)
    assert ("/cmd_vel_mux/input/navi", "geometry_msgs/Twist") in channels, channels
    assert ("/scan", "sensor_msgs/LaserScan") in channels, channels
    assert ("/arm/follow", "actionlib/TestAction") in channels, channels
    assert ("/arm/follow/goal", "actionlib/TestActionGoal") in channels, channels


def test_unreachable_master_is_one_clear_error(tmp_path):
    with pytest.raises(TransferError) as err:
        list_live_channels("http://127.0.0.1:9/")
    assert str(err.value).startswith("http://127.0.0.1:9/: cannot reach the ROS master"), str(err.value)
    assert err.value.code == Exit.NO_ROS


def test_keyboard_example_asks_with_the_thesis_prompt(ros_master, tmp_path):
    start_target_robot(ros_master, TURTLEBOT_TWIST)
    done = transfer(ros_master, tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", answer="1\n")
    assert done.returncode == 0, done.stderr
    prompt = ("Please select a topic for Twist from the list.\n"
              "The original topic was 'cmd_vel'. Input Example: 1\n"
              + "".join(f"{i}. {t}\n" for i, t in enumerate(TURTLEBOT_TWIST, 1)))
    assert prompt in done.stderr, done.stderr
    assert "rospy.Publisher('/cmd_vel_mux/input/navi', Twist" in (tmp_path / "out.py").read_text()
    assert "[user input]" in done.stdout and "user inputs 1" in done.stdout, done.stdout


def test_non_interactive_choice_is_stated_and_flagged(ros_master, tmp_path):
    start_target_robot(ros_master, TURTLEBOT_TWIST)
    done = transfer(ros_master, tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--non-interactive", "--json")
    assert done.returncode == 0, done.stderr
    channel = json.loads(done.stdout)["channels"][0]
    assert channel["replacement"] == TURTLEBOT_TWIST[rule_choice("cmd_vel", TURTLEBOT_TWIST)], channel
    assert "without asking" in channel["flagged"] and not channel["user_input"], channel


def test_codebase_choice_is_verified_on_the_master(ros_master, tmp_path):
    codebase = require_shared("codebase", "channel_counts.yaml")
    # the most probable name (navi) is not on this master; the next one the master has (teleop) is taken
    start_target_robot(ros_master, TURTLEBOT_TWIST[3:])
    done = transfer(ros_master, tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--codebase", str(codebase),
                    "--json", "--non-interactive")
    channel = json.loads(done.stdout)["channels"][0]
    assert channel["replacement"] == "/cmd_vel_mux/input/teleop", channel
    assert channel["method"].endswith("verified on the live master (A.2)"), channel
    assert "'cmd_vel_mux/input/navi' is not on the live master" in channel["flagged"], channel


def test_example_3_action_name_chosen_from_the_live_master(ros_master, tmp_path):
    # control_msgs cannot be installed here, so the Jaco driver's action topics are registered on the
    # real master through its own API, with the types the driver would register.
    proxy = ros_master.proxy()
    for ns in ("/effort_joint_traj_controller/follow_joint_traj", "/effort_finger_traj_controller/follow_joint_traj"):
        for suffix, kind in (("goal", "Goal"), ("cancel", None), ("status", None), ("feedback", "Feedback"),
                             ("result", "Result")):
            msg_type = f"{FJT}{kind}" if kind else {"cancel": "actionlib_msgs/GoalID",
                                                    "status": "actionlib_msgs/GoalStatusArray"}[suffix]
            code, msg, _ = proxy.registerSubscriber("/jaco_driver", f"{ns}/{suffix}", msg_type,
                                                    "http://127.0.0.1:9/")
            assert code == 1, msg
    done = transfer(ros_master, tmp_path, "follow_trajectory_ur5.py", "ur5", "j2n6s300", answer="2\n")
    assert done.returncode == 0, done.stderr
    assert ("Please select an action for FollowJointTrajectoryAction from the list.\n"
            "The original action was '/arm_controller/follow_joint_trajectory'. Input Example: 1\n"
            "1. /effort_finger_traj_controller/follow_joint_traj\n"
            "2. /effort_joint_traj_controller/follow_joint_traj\n") in done.stderr, done.stderr
    text = (tmp_path / "out.py").read_text()
    assert "SimpleActionClient('/effort_joint_traj_controller/follow_joint_traj'" in text, text
    assert "'j2n6s300_joint_6'" in text and "end-effector error" in done.stdout, done.stdout


def test_transferred_keyboard_program_drives_the_simulated_turtlebot_within_limits(ros_master, tmp_path):
    codebase = require_shared("codebase", "channel_counts.yaml")
    args = ["rosrun", "ltl_stack", "ros_code_transfer", str(DATA / "keyboard_jackal.py"), "--from", "jackal",
            "--to", "turtlebot", "--robots", str(require_shared("robots")), "-o", str(tmp_path / "kb.py"),
            "--codebase", str(codebase), "--non-interactive", "-q"]
    done = subprocess.run(args, env=ros_master.env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    topic = "/cmd_vel_mux/input/navi"
    ros_master.run(["rosrun", "ltl_stack", "sim_robot", f"cmd_vel:={topic}", "_cmd_timeout:=0"], name="sim_robot")
    record = tmp_path / "twists.jsonl"
    recorder = ros_master.run([sys.executable, str(DATA / "twist_recorder.py"), f"_topic:={topic}",
                               f"_out:={record}"], name="recorder")
    recorder.wait_output("recording", timeout=90)
    wait_for(lambda: len(ros_master.subscribers(topic)) >= 2, 90, f"the robot and the recorder on {topic}")
    # Both must be connected before the first key, or the recorder can miss it.
    program = ros_master.run([sys.executable, str(tmp_path / "kb.py"), "_keys:=udlr", "_listeners:=2"],
                             name="keyboard")
    wait_for(lambda: record.exists() and len(record.read_text().splitlines()) >= 4, 30,
             f"four Twists on {topic}\n{program.output()}")
    twists = [json.loads(line) for line in record.read_text().splitlines()]
    limits = load_limits(require_shared("robots", "limits", "turtlebot.yaml"))
    for twist in twists:
        for field, value in twist.items():
            assert limits[field].allows(value), (field, value)
    got = [(round(t["linear.x"], 6), round(t["angular.z"], 6)) for t in twists[:4]]
    assert got == [(0.2, 0.0), (-0.2, 0.0), (0.0, 0.675), (0.0, -0.675)], got


def test_a1_distribution_prompt_offers_only_names_the_master_has(ros_master, tmp_path):
    codebase = require_shared("codebase", "channel_counts.yaml")
    start_target_robot(ros_master, TURTLEBOT_TWIST[1:4])   # safety_controller, switch, teleop
    done = transfer(ros_master, tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--codebase", str(codebase),
                    "--choose-by-distribution", "--json", answer="2\n")
    assert done.returncode == 0, done.stderr
    assert ("The original topic was 'cmd_vel'. Input Example: 1\n"
            "1. cmd_vel_mux/input/teleop (8 uses, p=0.28)\n"
            "2. cmd_vel_mux/input/switch (1 use, p=0.03)\n") in done.stderr, done.stderr
    channel = json.loads(done.stdout)["channels"][0]
    assert channel["replacement"] == "/cmd_vel_mux/input/switch" and channel["user_input"], channel
    assert channel["method"].endswith("verified on the live master (A.2)"), channel
