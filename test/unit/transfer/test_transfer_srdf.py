"""SRDF planning groups, A.3 ranking and thesis Example 5 (Fetch -> PR2)."""
from pathlib import Path

import pytest
from helpers import require_shared

from ltl_stack.errors import UserError
from ltl_stack.transfer.errors import TransferError
from ltl_stack.transfer.profiles import load_profile
from ltl_stack.transfer.srdf import check_against_urdf, load_srdf, parse_srdf, rank_groups, similarity
from ltl_stack.transfer.transfer import TransferOptions, transfer_program
from ltl_stack.transfer.urdf_tree import load_urdf_tree

DATA = Path(__file__).resolve().parents[2] / "data" / "transfer"


def pr2():
    robots = require_shared("robots")
    return load_srdf(robots / "srdf" / "pr2.srdf"), load_urdf_tree(robots / "urdf" / "pr2.urdf")


def test_ratcliff_obershelp_ranking_of_pr2_groups_against_arm_with_torso():
    srdf, _ = pr2()
    ranked = rank_groups("arm_with_torso", srdf)
    assert [name for name, _ in ranked[:3]] == ["arms_and_torso", "left_arm_and_torso", "right_arm_and_torso"]
    assert ranked[1][1] == pytest.approx(2 * 10 / (14 + 18)), ranked   # difflib: 2M/T
    assert similarity("arm", "arm") == 1.0


def test_tip_links_of_pr2_groups():
    srdf, urdf = pr2()
    got = {name: srdf.tip_link(name, urdf) for name in ("left_arm_and_torso", "right_arm", "arms", "torso")}
    assert got == {"left_arm_and_torso": "l_wrist_roll_link", "right_arm": "r_wrist_roll_link",
                   "arms": None, "torso": "torso_lift_link"}, got


def test_fetch_joint_list_group_tip_comes_from_the_urdf():
    robots = require_shared("robots")
    srdf, urdf = load_srdf(robots / "srdf" / "fetch.srdf"), load_urdf_tree(robots / "urdf" / "fetch.urdf")
    assert srdf.tip_link("arm_with_torso", urdf) == "wrist_roll_link"


def example_5(ask):
    robots = require_shared("robots")
    text = (DATA / "moveit_fetch.py").read_text()
    return text, transfer_program(text, load_profile(robots, "fetch"), load_profile(robots, "pr2"),
                                  TransferOptions(ask=ask))


def test_example_5_user_chooses_the_left_arm_group():
    asked = []

    def ask(word, msg_type, original, options):
        asked.append((word, original, list(options[:3])))
        return options.index("left_arm_and_torso")

    text, result = example_5(ask)
    assert asked == [("MoveIt group", "arm_with_torso",
                      ["arms_and_torso", "left_arm_and_torso", "right_arm_and_torso"])], asked
    assert 'MoveGroupInterface("left_arm_and_torso", "base_link")' in result.text
    assert "gripper_frame = 'l_wrist_roll_link'" in result.text
    assert result.report.user_inputs == 1 and result.report.channels_replaced == 2, result.report.summary()
    assert len(result.text.splitlines()) == len(text.splitlines())


def test_example_5_non_interactive_takes_the_best_group_with_one_pose_frame():
    _, result = example_5(None)
    group = result.report.channels[0]
    assert group.replacement == "left_arm_and_torso" and "arms_and_torso" in group.flagged, group
    assert result.report.channels[1].replacement == "l_wrist_roll_link"


def test_inconsistent_srdf_names_the_file_and_the_group():
    robots = require_shared("robots")
    srdf = load_srdf(robots / "srdf" / "nao.srdf")
    with pytest.raises(TransferError) as err:
        check_against_urdf(srdf, load_urdf_tree(robots / "urdf" / "nao_robot_v3.urdf"))
    assert "nao.srdf: group 'left_leg': link 'LHip' is not in the URDF" in str(err.value), str(err.value)


@pytest.mark.parametrize("text, message", [
    ("<robot><group/></robot>", "a <group> has no name"),
    ("<robot><group name='a'><chain base_link='x'/></group></robot>", "group 'a' <chain>: a chain needs"),
    ("<robot><group name='a'><group name='b'/></group></robot>", "unknown subgroup 'b'"),
    ("<robot name='r'><group name='a'>", "not valid XML"),
])
def test_bad_srdf(text, message):
    with pytest.raises(UserError) as err:
        parse_srdf(text, "r.srdf")
    assert str(err.value).startswith("r.srdf:") and message in str(err.value), str(err.value)


def test_a_planning_frame_the_target_lacks_is_unresolved():
    robots = require_shared("robots")
    text = (DATA / "moveit_fetch.py").read_text().replace('"arm_with_torso", "base_link"',
                                                          '"arm_with_torso", "torso_fixed_link"')
    result = transfer_program(text, load_profile(robots, "fetch"), load_profile(robots, "pr2"))
    assert [(u.what, u.line) for u in result.report.unresolved] == [("planning frame 'torso_fixed_link'", 12)], \
        result.report.unresolved
