"""The arms' joints and MoveIt groups shipped in the package (our YAML, transfer/robot_data.py):
they agree with the URDF/SRDF of ../shared, give the same transfers, and bad files are one clear line."""
from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest
from helpers import REPO_ROOT, require_shared
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.errors import Exit
from ltl_stack.transfer.errors import TransferError
from ltl_stack.transfer.profiles import SHIPPED_ROBOTS, load_profile
from ltl_stack.transfer.srdf import load_srdf
from ltl_stack.transfer.thesis_table import main as table_main
from ltl_stack.transfer.urdf import load_urdf

_spec = importlib.util.spec_from_file_location("derive_robot_data", REPO_ROOT / "tools" / "derive_robot_data.py")
derive = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(derive)

ARMS = {"ur5": False, "j2n6s300": True, "j2s7s300": True, "jaco": True, "pepper": True, "nao": True,
        "fetch": True, "pr2": True, "youbot": False}   # robot: has MoveIt groups


def test_every_arm_of_the_thesis_ships_its_joints_and_groups():
    for robot, groups in ARMS.items():
        profile = load_profile(SHIPPED_ROBOTS, robot)
        assert profile.urdf is not None and profile.urdf.parent == SHIPPED_ROBOTS / "joints", profile
        assert (profile.srdf is not None) == groups, profile
        assert load_urdf(profile.urdf).joints and (not groups or load_srdf(profile.srdf).groups)


@pytest.mark.parametrize("robot", sorted(ARMS))
def test_shipped_data_is_exactly_what_the_shared_urdf_and_srdf_say(robot):
    shared = load_profile(require_shared("robots"), robot)
    ours = load_profile(SHIPPED_ROBOTS, robot)
    derive.check_same(shared.urdf, ours.urdf)      # tree, origins (bit for bit), axes, limits
    if shared.srdf is not None:
        derive.check_same(shared.srdf, ours.srdf)  # groups, chains, end effectors, virtual joints
    assert (shared.srdf is None) == (ours.srdf is None)


def test_table_2_5_and_the_programs_are_the_same_with_the_shipped_and_the_shared_robots(tmp_path, capsys):
    shared = require_shared("robots")
    runs = {}
    for name, extra in (("shipped", []), ("shared", ["--robots", str(shared), "--codebase",
                                                     str(require_shared("codebase", "channel_counts.yaml"))])):
        assert table_main(["--json", "--keep", str(tmp_path / name), *extra]) == Exit.OK
        rows = json.loads(capsys.readouterr().out)
        for row in rows:
            row["ours"].pop("time_s")
        runs[name] = [(r["example"], r["exit_code"], r["ours"]) for r in rows]
    assert runs["shipped"] == runs["shared"]
    programs = sorted(p.name for p in (tmp_path / "shipped").iterdir())
    assert len(programs) == 7 and programs == sorted(p.name for p in (tmp_path / "shared").iterdir())
    for name in programs:
        assert (tmp_path / "shipped" / name).read_text() == (tmp_path / "shared" / name).read_text(), name


def _robot(tmp_path, joints: str, groups: str | None = None):
    (tmp_path / "joints.yaml").write_text("robot: arm\nroot: base\njoints:\n" + joints)
    profile = "urdf: joints.yaml\n"
    if groups is not None:
        (tmp_path / "groups.yaml").write_text("robot: arm\n" + groups)
        profile += "srdf: groups.yaml\n"
    (tmp_path / "arm.yaml").write_text(profile)
    return load_profile(tmp_path, "arm")


GOOD = "  j1: {type: revolute, parent: base, child: l1, axis: [0, 0, 1], limit: [-1, 1, 2]}\n"


@pytest.mark.parametrize("joints, groups, message", [
    ("  j1: {type: revolute, parent: base}\n", None, "joint 'j1': child is needed"),
    ("  j1: {type: revolute, parent: base, child: l1, limit: [-1, 1]}\n", None,
     "joint 'j1' limit: must be a list of 3 numbers (or null)"),
    ("  j1: {type: revolute, parent: base, child: l1, xyz: [0, 0, 1]}\n", None,
     "joint 'j1': an origin needs both xyz and rpy"),
    ("  j1: {type: bendy, parent: base, child: l1}\n", None, "joint 'j1': unknown joint type 'bendy'"),
    ("  j1: {type: revolute, parent: base, child: l1, colour: red}\n", None, "unknown key(s) ['colour']"),
    (GOOD, "groups:\n  arm: {subgroups: [hand]}\n", "group 'arm': unknown subgroup 'hand'"),
    (GOOD, "groups:\n  arm: {chains: [[base]]}\n", "chains must be a list of [base_link, tip_link]"),
    (GOOD, "groups:\n  arm: {joints: [j1]}\nend_effectors:\n  - {name: e, parent_link: l1, group: hand}\n",
     "end_effector 'e': unknown group 'hand'"),
])
def test_bad_robot_data_is_one_line_naming_file_and_element(tmp_path, joints, groups, message):
    profile = _robot(tmp_path, joints, groups)
    with pytest.raises(TransferError) as err:
        load_urdf(profile.urdf)
        load_srdf(profile.srdf)
    text = str(err.value)
    assert "\n" not in text and text.startswith(str(tmp_path)) and message in text, text


def test_a_continuous_joint_without_limits_turns_once_each_way_as_in_a_urdf(tmp_path):
    profile = _robot(tmp_path, "  j1: {type: continuous, parent: base, child: l1, axis: [0, 0, 1]}\n")
    model = load_urdf(profile.urdf)
    assert model.limits("j1") == (-np.pi, np.pi) and model.velocity_limit("j1") is None


_value = st.floats(-10, 10, allow_nan=False, allow_subnormal=False)


@settings(max_examples=25, deadline=None)
@given(xyz=st.lists(_value, min_size=3, max_size=3), rpy=st.lists(_value, min_size=3, max_size=3),
       axis=st.lists(_value, min_size=3, max_size=3).filter(lambda a: any(abs(v) > 1e-3 for v in a)),
       limit=st.tuples(_value, _value, st.floats(0.01, 10)))
def test_derived_data_loads_into_the_same_model_as_its_urdf(tmp_path_factory, xyz, rpy, axis, limit):
    """Any origin, axis and limit survive the YAML exactly: the same matrices as yourdfpy's."""
    folder = tmp_path_factory.mktemp("urdf")
    urdf = folder / "arm.urdf"
    urdf.write_text(f"""<robot name="arm"><link name="base"/><link name="l1"/><link name="l2"/>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
<origin xyz="{' '.join(map(repr, xyz))}" rpy="{' '.join(map(repr, rpy))}"/>
<axis xyz="{' '.join(map(repr, axis))}"/>
<limit lower="{min(limit[:2])!r}" upper="{max(limit[:2])!r}" velocity="{limit[2]!r}" effort="1"/></joint>
<joint name="j2" type="fixed"><parent link="l1"/><child link="l2"/></joint></robot>""")
    ours = folder / "arm.yaml"
    ours.write_text(derive.dump(derive.joints_data(urdf), "# test"))
    derive.check_same(urdf, ours)
    chain = load_urdf(ours).chain("base", "l2")
    assert [j.name for j in chain] == ["j1", "j2"]
