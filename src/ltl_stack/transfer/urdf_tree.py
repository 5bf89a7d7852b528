"""The link/joint tree of a URDF, read with ElementTree: names, types, parents and children.

Enough for checking an SRDF and finding pose frames, and cheap to import; kinematics (numpy, yourdfpy)
is in ``urdf``, which the transfer loads only for programs that move joints.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

from ltl_stack.errors import InputError
from ltl_stack.inputs import read_text

from .errors import TransferError
from .robot_data import is_robot_data, load_joints

ACTUATED = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class JointInfo:
    name: str
    type: str
    parent: str
    child: str


class UrdfTree:
    """The link/joint tree of a URDF (names, types, parent and child), read quickly with ElementTree.

    Enough for checking an SRDF and finding pose frames; kinematics needs :class:`UrdfModel`.
    """

    def __init__(self, joints: list[JointInfo], links: set[str], name: str, file: str):
        self.file = file
        self.name = name
        self.joints = {j.name: j for j in joints}
        self.links = links
        self.parent_joint = {j.child: j for j in joints}
        self.children: dict[str, list] = {}
        for j in joints:
            self.children.setdefault(j.parent, []).append(j)
        for j in joints:
            for link in (j.parent, j.child):
                if link not in self.links:
                    raise TransferError(f"link {link!r} is not defined", file, f"joint {j.name!r}")
            if j.type not in ACTUATED + ("fixed", "floating", "planar"):
                raise TransferError(f"unknown joint type {j.type!r}", file, f"joint {j.name!r}")

    def has_joint(self, name: str) -> bool:
        return name in self.joints

    def has_link(self, name: str) -> bool:
        return name in self.links

    def joint(self, name: str):
        if name not in self.joints:
            raise TransferError(f"no joint {name!r}", self.file)
        return self.joints[name]

    def path_to(self, link: str) -> list:
        """Joints from the root to ``link``."""
        path = []
        while link in self.parent_joint:
            j = self.parent_joint[link]
            path.append(j)
            link = j.parent
        return list(reversed(path))

    def deepest_child(self, joint_names: list[str]) -> str:
        """The child link of the joint that lies deepest on one serial path through all these joints."""
        known = [n for n in joint_names if n in self.joints]
        if not known:
            raise TransferError(f"none of the joints {joint_names} is in the URDF", self.file)
        deepest = max(known, key=lambda n: len(self.path_to(self.joints[n].child)))
        on_path = {j.name for j in self.path_to(self.joints[deepest].child)}
        if not set(known) <= on_path:
            raise TransferError(f"joints {sorted(set(known) - on_path)} are not on one chain with "
                                f"{deepest!r}", self.file)
        return self.joints[deepest].child

    def leaf_chains(self) -> list[list]:
        """Root-to-leaf joint paths (for choosing a chain when nothing else says which)."""
        leaves = [link for link in self.links if link not in self.children]
        return [self.path_to(leaf) for leaf in sorted(leaves)]


def parse_xml(text: str, file: str) -> ElementTree.Element:
    """The root element of an XML document; ``InputError`` with the line when it is not well-formed."""
    try:
        return ElementTree.fromstring(text)
    except ElementTree.ParseError as err:
        line = err.position[0] if getattr(err, "position", None) else 0
        raise InputError(file, f"not valid XML: {str(err).split(': line ')[0]}", line) from None


@functools.lru_cache(maxsize=32)
def cached_tree(path: str, mtime: float) -> tuple[UrdfTree, str]:
    """The checked tree of a URDF and its text, cached per path and modification time."""
    text = read_text(path, "URDF file")
    root = parse_xml(text, path)
    if root.tag != "robot":
        raise TransferError(f"root element is <{root.tag}>, expected <robot>", path)
    joints = []
    for elem in root.findall("joint"):
        name = elem.get("name")
        parent, child = elem.find("parent"), elem.find("child")
        if not name or parent is None or child is None or not parent.get("link") or not child.get("link"):
            raise TransferError("a joint needs a name, <parent link=...> and <child link=...>", path,
                                f"joint {name!r}")
        joints.append(JointInfo(name, elem.get("type", ""), parent.get("link"), child.get("link")))
    links = {e.get("name") for e in root.findall("link")}
    return UrdfTree(joints, links, root.get("name", ""), path), text


@functools.lru_cache(maxsize=32)
def cached_data_tree(path: str, mtime: float) -> tuple[UrdfTree, dict]:
    """The tree of our joints file (``robot_data``) and its checked data, cached like ``cached_tree``."""
    data = load_joints(path)
    joints = [JointInfo(name, j["type"], j["parent"], j["child"]) for name, j in data["joints"].items()]
    return UrdfTree(joints, data["links"], data["robot"], path), data


def modification_time(path: str | Path) -> float:
    """The file's modification time (the cache key beside its path); an error naming it if unreadable."""
    try:
        return Path(path).stat().st_mtime
    except OSError as err:
        raise TransferError(f"cannot read URDF: {err.strerror}", str(path)) from None


def load_urdf_tree(path: str | Path) -> UrdfTree:
    """Only the link/joint names of a URDF or of our joints file (fast: no kinematics)."""
    load = cached_data_tree if is_robot_data(path) else cached_tree
    return load(str(path), modification_time(path))[0]
