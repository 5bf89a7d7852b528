"""MoveIt's Python APIs beyond the group name, and joint arrays of one length per trajectory."""
import ast
import textwrap
from pathlib import Path

import pytest
from helpers import require_shared

from ltl_stack.transfer.profiles import load_profile
from ltl_stack.transfer.transfer import TransferRefused, transfer_program

STYLES = Path(__file__).resolve().parents[2] / "data" / "transfer" / "styles"


def transfer(program, source, target, text=None):
    robots = require_shared("robots")
    text = text if text is not None else (STYLES / program).read_text()
    return transfer_program(text, load_profile(robots, source), load_profile(robots, target), filename=program)


def array_length(text):
    node = ast.parse(text.strip(), mode="eval").body
    return len(node.elts)


def line_of(text, n):
    return text.splitlines()[n - 1].strip()


def unresolved(result):
    return [(u.line, u.what) for u in result.report.unresolved]


def test_pick_place_interface_and_joint_positions_follow_the_target_group():
    result = transfer("pick_place_fetch.py", "fetch", "pr2")
    assert line_of(result.text, 14) == "self.pickplace = PickPlaceInterface('left_arm', 'left_gripper', verbose=True)"
    assert line_of(result.text, 15) == "self.move_group = MoveGroupInterface('left_arm', 'base_link')"
    assert result.report.retargeting["target_rule"] == "the MoveIt group 'left_arm' the program commands"
    names = result.report.retargeting["target_joints"]
    assert names[0] == "l_shoulder_pan_joint" and len(names) == 7, names
    assert "'l_shoulder_pan_joint'" in result.text and "'shoulder_pan_joint'" not in result.text
    tucked = next(p for p in result.report.parameters if p.what == "positions (variable tucked)")
    assert array_length(tucked.replacement) == 7, tucked
    assert unresolved(result) == [], result.report.unresolved   # 'gripper' is a group, not a planning frame


def test_commander_joint_names_and_named_states_not_on_the_target_are_listed():
    result = transfer("commander_fetch.py", "fetch", "pr2")
    assert line_of(result.text, 10) == "group = moveit_commander.MoveGroupCommander('left_arm')"
    assert unresolved(result) == [(11, "joint 'shoulder_pan_joint'"), (11, "joint 'elbow_flex_joint'"),
                                  (13, "joint 'wrist_flex_joint'"), (15, "MoveIt named state 'tucked'")]
    assert "Everything was resolved" not in result.report.to_text()


def test_a_function_whose_arrays_are_not_literals_keeps_all_of_them():
    before = (STYLES / "ur_mover_state.py").read_text()
    result = transfer("ur_mover_state.py", "ur5", "pr2")
    # go_home: names, positions and velocities all 8 entries
    assert "positions=HOME, velocities=[0] * 8," in result.text, result.text
    assert array_length(result.text.split("HOME = ")[1].split("\n")[0]) == 8
    # hold: names and positions come from the joint state: its velocities stay as the source had them
    assert line_of(before, 26) in result.text and "velocities=[0] * 6" in line_of(before, 26)
    assert (25, "joint trajectory in hold()") in unresolved(result), result.report.unresolved


def test_arrays_that_would_differ_in_length_are_refused_naming_the_lines():
    code = textwrap.dedent("""\
        from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
        traj = JointTrajectory()
        traj.joint_names = ['shoulder_pan_joint', 'shoulder_lift_joint', 'elbow_joint',
                            'wrist_1_joint', 'wrist_2_joint', 'wrist_3_joint']
        traj.points = [JointTrajectoryPoint(positions=[0.0, -1.0, 1.0, 0.0, 0.0, 0.0],
                                            velocities=[0.1, 0.1, 0.1, 0.1, 0.1])]
    """)
    with pytest.raises(TransferRefused) as err:
        transfer("bad_lengths.py", "ur5", "pr2", code)
    message = str(err.value)
    assert "joint arrays of different lengths at module level" in message, message
    assert "line 3 joint_names: 8" in message and "line 5 velocities: 5" in message, message


def test_literals_that_computed_arrays_read_are_kept():
    """A function that reorders the module's joint lists ([NAMES[i] for i in order]) would command other
    joints if those lists were retargeted: they are kept, and said so."""
    code = textwrap.dedent("""\
        from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
        NAMES = ['shoulder_pan_joint', 'shoulder_lift_joint', 'elbow_joint',
                 'wrist_1_joint', 'wrist_2_joint', 'wrist_3_joint']
        Q1 = [2.2, 0, -1.57, 0, 0, 0]
        def move(traj):
            traj.joint_names = NAMES
            traj.points = [JointTrajectoryPoint(positions=Q1, velocities=[0] * 6)]
        def move_disordered(traj, order):
            traj.joint_names = [NAMES[i] for i in order]
            traj.points = [JointTrajectoryPoint(positions=[Q1[i] for i in order], velocities=[0] * 6)]
    """)
    result = transfer("disordered.py", "ur5", "pr2", code)
    assert result.text == code
    assert (2, "joint lists") in unresolved(result) and (9, "joint trajectory in move_disordered()") in \
        unresolved(result), result.report.unresolved
