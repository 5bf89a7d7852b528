"""Our compact robot data: the facts of a URDF and an SRDF that code transfer uses, as YAML.

The package ships these for the thesis' arms (``robots/joints/*.yaml``, ``robots/groups/*.yaml``), so
arm retargeting (§2.5.2 B.3) and MoveIt group matching (A.3) need no URDF or SRDF at run time. A robot
profile's ``urdf:`` or ``srdf:`` may name such a file instead of the XML one (chosen by the ``.yaml``
suffix). ``tools/derive_robot_data.py`` writes them from a URDF/SRDF.

A joints file (what ``urdf_tree`` and ``urdf`` read from a URDF)::

    robot: ur5
    root: world                        # the link no joint has as child
    links: [...]                       # only links no joint names (rare)
    joints:                            # in the URDF's order
      shoulder_pan_joint: {type: revolute, parent: base_link, child: shoulder_link,
                           xyz: [0, 0, 0.089159], rpy: [0, 0, 0],    # <origin>, when the URDF has one
                           axis: [0, 0, 1],                          # <axis>, for moving joints
                           limit: [-6.28, 6.28, 3.15]}               # <limit> lower, upper, velocity

A groups file (what ``srdf`` reads from an SRDF; collision pairs are not needed)::

    robot: pr2
    virtual_joints: [world_joint]
    groups:
      right_arm: {chains: [[torso_lift_link, r_wrist_roll_link]]}   # also joints, links, subgroups
    end_effectors:
      - {name: r_end_effector, parent_link: r_wrist_roll_link, group: r_gripper, parent_group: right_arm}
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

from ltl_stack.inputs import load_yaml

from .errors import TransferError

JOINT_KEYS = {"type", "parent", "child", "xyz", "rpy", "axis", "limit"}
GROUP_KEYS = ("joints", "links", "chains", "subgroups")
END_EFFECTOR_KEYS = ("name", "parent_link", "group", "parent_group")


def is_robot_data(path: str | Path) -> bool:
    """Whether a profile's urdf/srdf file is our YAML data rather than the XML description."""
    return Path(path).suffix in (".yaml", ".yml")


def _mapping(value: Any, file: str, where: str) -> dict:
    if not isinstance(value, dict):
        raise TransferError("must be a mapping", file, where)
    return value


def _names(value: Any, file: str, where: str) -> list[str]:
    if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
        raise TransferError("must be a list of names", file, where)
    return value


def _numbers(value: Any, size: int, file: str, where: str, optional: bool = False) -> list:
    ok = isinstance(value, list) and len(value) == size and all(
        (v is None and optional) or (isinstance(v, (int, float)) and not isinstance(v, bool)) for v in value)
    if not ok:
        raise TransferError(f"must be a list of {size} numbers" + (" (or null)" if optional else ""), file, where)
    return [None if v is None else float(v) for v in value]


def load_joints(path: str | Path) -> dict:
    """A checked joints file: ``robot``, ``root``, ``links`` (all of them) and ``joints`` (name -> fields)."""
    file = str(path)
    data = _mapping(load_yaml(path, "robot joints file"), file, "top level")
    for key in ("robot", "root"):
        if not isinstance(data.get(key), str):
            raise TransferError("a name is needed", file, key)
    joints = {}
    for name, fields in _mapping(data.get("joints"), file, "joints").items():
        where = f"joint {name!r}"
        fields = _mapping(fields, file, where)
        unknown = set(fields) - JOINT_KEYS
        if unknown:
            raise TransferError(f"unknown key(s) {sorted(unknown)}", file, where)
        for key in ("type", "parent", "child"):
            if not isinstance(fields.get(key), str):
                raise TransferError(f"{key} is needed", file, where)
        joint = {key: fields[key] for key in ("type", "parent", "child")}
        for key, size, optional in (("xyz", 3, False), ("rpy", 3, False), ("axis", 3, False),
                                    ("limit", 3, True)):
            joint[key] = _numbers(fields[key], size, file, f"{where} {key}", optional) if key in fields else None
        if (joint["xyz"] is None) != (joint["rpy"] is None):
            raise TransferError("an origin needs both xyz and rpy", file, where)
        joints[str(name)] = joint
    links = {data["root"]} | set(_names(data.get("links", []), file, "links"))
    links |= {j[end] for j in joints.values() for end in ("parent", "child")}
    return {"robot": data["robot"], "root": data["root"], "links": links, "joints": joints}


def load_groups(path: str | Path) -> dict:
    """A checked groups file: ``robot``, ``virtual_joints``, ``groups`` and ``end_effectors``."""
    file = str(path)
    data = _mapping(load_yaml(path, "robot groups file"), file, "top level")
    if not isinstance(data.get("robot"), str):
        raise TransferError("a name is needed", file, "robot")
    groups = {}
    for name, fields in _mapping(data.get("groups"), file, "groups").items():
        where = f"group {name!r}"
        fields = _mapping(fields or {}, file, where)
        unknown = set(fields) - set(GROUP_KEYS)
        if unknown:
            raise TransferError(f"unknown key(s) {sorted(unknown)}", file, where)
        group = {key: _names(fields.get(key, []), file, f"{where} {key}") for key in ("joints", "links", "subgroups")}
        chains = fields.get("chains", [])
        if not isinstance(chains, list) or not all(isinstance(c, list) and len(c) == 2 for c in chains):
            raise TransferError("chains must be a list of [base_link, tip_link]", file, where)
        group["chains"] = [tuple(_names(c, file, f"{where} chains")) for c in chains]
        groups[str(name)] = group
    eefs = []
    for i, fields in enumerate(data.get("end_effectors") or []):
        fields = _mapping(fields, file, f"end_effectors[{i}]")
        if not all(isinstance(fields.get(k), str) for k in END_EFFECTOR_KEYS[:3]):
            raise TransferError("an end effector needs name, parent_link and group", file, f"end_effectors[{i}]")
        eefs.append({k: fields.get(k) for k in END_EFFECTOR_KEYS})
    virtual = _names(data.get("virtual_joints", []), file, "virtual_joints")
    return {"robot": data["robot"], "groups": groups, "end_effectors": eefs, "virtual_joints": virtual}
