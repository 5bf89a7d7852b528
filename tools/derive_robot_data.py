#!/usr/bin/env python3
"""Write the package's robot joints and groups files (transfer/robot_data.py's format) from URDF/SRDF facts.

    python tools/derive_robot_data.py [--robots ../shared/robots] [--out src/ltl_stack/transfer/robots]

For each arm of the thesis' robots it keeps what code transfer reads (joint tree, origins, axes, limits;
planning groups, end effectors, virtual joints) and leaves out the rest (meshes, inertia, collision
pairs). It then loads each written file and checks that it gives the same model as the description.
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import yaml

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

from ltl_stack.transfer.profiles import load_profile  # noqa: E402
from ltl_stack.transfer.srdf import load_srdf  # noqa: E402
from ltl_stack.transfer.urdf import load_urdf  # noqa: E402

#: the arms of the thesis' chapter 2 examples and of the other robots its tables name
ROBOTS = ("ur5", "j2n6s300", "j2s7s300", "jaco", "pepper", "nao", "fetch", "pr2", "youbot")


def _numbers(values) -> list[float] | None:
    return None if values is None else [None if v is None else float(v) for v in values]


def joints_data(urdf_path: Path) -> dict:
    """The joints file's content: the tree, origins (as the URDF writes them), axes and limits."""
    model = load_urdf(urdf_path)
    root = ElementTree.parse(urdf_path).getroot()
    joints = {}
    for elem in root.findall("joint"):
        name = elem.get("name")
        info, kin = model.joint(name), model.kinematics[name]
        joint = {"type": info.type, "parent": info.parent, "child": info.child}
        origin = elem.find("origin")
        if origin is not None:
            joint["xyz"] = [float(v) for v in origin.get("xyz", "0 0 0").split()]
            joint["rpy"] = [float(v) for v in origin.get("rpy", "0 0 0").split()]
        if info.type != "fixed" and kin.axis is not None:
            joint["axis"] = _numbers(kin.axis)
        if kin.limit is not None:
            joint["limit"] = _numbers(kin.limit)
        joints[name] = joint
    roots = sorted(model.links - set(model.parent_joint))
    named = {j.parent for j in model.joints.values()} | {j.child for j in model.joints.values()}
    data = {"robot": model.name, "root": roots[0] if len(roots) == 1 else next(r for r in roots if r in named)}
    lone = sorted(model.links - named - {data["root"]})
    if lone:
        data["links"] = lone
    data["joints"] = joints
    return data


def groups_data(srdf_path: Path) -> dict:
    """The groups file's content: planning groups, end effectors, virtual joints (no collision pairs)."""
    srdf = load_srdf(srdf_path)
    groups = {}
    for name, group in srdf.groups.items():
        fields = {key: value for key, value in (("joints", group.joints), ("links", group.links),
                                                ("chains", [list(c) for c in group.chains]),
                                                ("subgroups", group.subgroups)) if value}
        groups[name] = fields
    eefs = [{k: v for k, v in (("name", e.name), ("parent_link", e.parent_link), ("group", e.group),
                               ("parent_group", e.parent_group)) if v is not None} for e in srdf.end_effectors]
    data = {"robot": srdf.robot}
    if srdf.virtual_joints:
        data["virtual_joints"] = list(srdf.virtual_joints)
    data["groups"] = groups
    if eefs:
        data["end_effectors"] = eefs
    return data


def _flow(value) -> str:
    text = yaml.safe_dump(value, default_flow_style=True, width=10**6, sort_keys=False)
    return re.sub(r"\n\.\.\.\n$", "", text).strip()


def dump(data: dict, header: str) -> str:
    """YAML with one line per joint, group or end effector (floats written so they read back exactly)."""
    lines = [header]
    for key, value in data.items():
        if isinstance(value, dict):
            lines.append(f"{key}:")
            lines += [f"  {name}: {_flow(item)}" for name, item in value.items()]
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            lines.append(f"{key}:")
            lines += [f"  - {_flow(item)}" for item in value]
        else:
            lines.append(f"{key}: {_flow(value)}")
    return "\n".join(lines) + "\n"


def check_same(described: Path, ours: Path) -> None:
    """Our file must load into the same model as the URDF/SRDF it came from (exactly)."""
    if described.suffix == ".srdf":
        a, b = load_srdf(described), load_srdf(ours)
        assert (a.robot, a.groups, a.end_effectors, a.virtual_joints) == (b.robot, b.groups, b.end_effectors,
                                                                             b.virtual_joints), ours
        return
    a, b = load_urdf(described), load_urdf(ours)
    assert (a.name, a.links, a.joints) == (b.name, b.links, b.joints), ours
    for name, ka in a.kinematics.items():
        kb = b.kinematics[name]
        assert ka.limit == kb.limit, (ours, name)
        assert (ka.origin is None) == (kb.origin is None) and np.array_equal(ka.origin, kb.origin), (ours, name)
        if a.joints[name].type != "fixed":
            assert np.array_equal(ka.axis, kb.axis), (ours, name)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=Path, default=REPO.parent / "shared" / "robots")
    parser.add_argument("--out", type=Path, default=REPO / "src" / "ltl_stack" / "transfer" / "robots")
    args = parser.parse_args()
    for robot in ROBOTS:
        profile = load_profile(args.robots, robot)
        for described, kind, make in ((profile.urdf, "joints", joints_data), (profile.srdf, "groups", groups_data)):
            if described is None:
                continue
            out = args.out / kind / f"{robot}.yaml"
            out.parent.mkdir(parents=True, exist_ok=True)
            what = "joint tree, origins, axes and limits" if kind == "joints" else "planning groups and end effectors"
            out.write_text(dump(make(described), f"# {robot}: the {what} of {described.name}\n"
                                                 "# (our format, transfer/robot_data.py; by tools/derive_robot_data.py)"))
            check_same(described, out)
            print(f"{out.relative_to(REPO) if REPO in out.parents else out}: from {described.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
