"""SRDF (MoveIt semantic description) reading: planning groups, chains, end effectors (thesis A.3).

Groups may list joints, links, chains (``base_link``/``tip_link``) and subgroups. The pose frame of a
group is the tip of its chain, or else the SRDF end effector attached to it, or else (with the URDF)
the deepest link its joints reach.
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass, field
from pathlib import Path

from ltl_stack.inputs import read_text

from .errors import TransferError
from .robot_data import is_robot_data, load_groups
from .urdf_tree import parse_xml


@dataclass
class PlanningGroup:
    name: str
    joints: list[str] = field(default_factory=list)
    links: list[str] = field(default_factory=list)
    chains: list[tuple[str, str]] = field(default_factory=list)  # (base_link, tip_link)
    subgroups: list[str] = field(default_factory=list)


@dataclass
class EndEffector:
    name: str
    parent_link: str
    group: str
    parent_group: str | None = None


@dataclass
class Srdf:
    robot: str
    groups: dict[str, PlanningGroup]
    end_effectors: list[EndEffector]
    file: str = "<srdf>"
    virtual_joints: list[str] = field(default_factory=list)

    def group(self, name: str) -> PlanningGroup:
        if name not in self.groups:
            raise TransferError(f"no planning group {name!r} (groups: {', '.join(self.groups)})", self.file)
        return self.groups[name]

    def all_joints(self, name: str, _seen: frozenset = frozenset()) -> list[str]:
        """Joints of a group including its subgroups (chains are expanded by the caller, with the URDF)."""
        group = self.group(name)
        joints = list(group.joints)
        for sub in group.subgroups:
            if sub not in _seen:
                joints += [j for j in self.all_joints(sub, _seen | {name}) if j not in joints]
        return joints

    def all_chains(self, name: str, _seen: frozenset = frozenset()) -> list[tuple[str, str]]:
        group = self.group(name)
        chains = list(group.chains)
        for sub in group.subgroups:
            if sub not in _seen:
                chains += self.all_chains(sub, _seen | {name})
        return chains

    def tip_link(self, name: str, urdf=None) -> str | None:
        """The pose frame of a group: its chain tip, its end effector's parent link, or its deepest link.

        None when the group has no single tip (several arms, or no joints that form one chain).
        """
        group = self.group(name)
        tips = {tip for _, tip in self.all_chains(name)}
        if len(tips) > 1:
            return None
        if tips:
            return tips.pop()
        for eef in self.end_effectors:
            if eef.parent_group == name:
                return eef.parent_link
        joints = [j for j in self.all_joints(name) if j not in self.virtual_joints]
        if urdf is not None and joints:
            try:
                return urdf.deepest_child(joints)
            except TransferError:
                return None
        links = set(group.links)
        for eef in self.end_effectors:
            if eef.parent_link in links:
                return eef.parent_link
        return None


def parse_srdf(text: str, file: str = "<srdf>") -> Srdf:
    """Read an SRDF document; a clear error names the file and the offending element."""
    root = parse_xml(text, file)
    if root.tag != "robot":
        raise TransferError(f"root element is <{root.tag}>, expected <robot>", file)
    groups: dict[str, PlanningGroup] = {}
    for elem in root.findall("group"):
        name = elem.get("name")
        if not name:
            raise TransferError("a <group> has no name", file, f"line {_line(text, elem)}")
        group = PlanningGroup(name)
        for child in elem:
            where = f"group {name!r} <{child.tag}>"
            if child.tag in ("joint", "link", "group"):
                if not child.get("name"):
                    raise TransferError("missing attribute 'name'", file, where)
                {"joint": group.joints, "link": group.links, "group": group.subgroups}[child.tag].append(
                    child.get("name"))
            elif child.tag == "chain":
                base, tip = child.get("base_link"), child.get("tip_link")
                if not base or not tip:
                    raise TransferError("a chain needs base_link and tip_link", file, where)
                group.chains.append((base, tip))
        groups[name] = group
    _check_subgroups(groups, file)
    eefs = []
    for elem in root.findall("end_effector"):
        name, parent_link, group = elem.get("name"), elem.get("parent_link"), elem.get("group")
        if not (name and parent_link and group):
            raise TransferError("an end_effector needs name, parent_link and group", file,
                                f"end_effector {name!r}")
        if group not in groups:
            raise TransferError(f"unknown group {group!r}", file, f"end_effector {name!r}")
        eefs.append(EndEffector(name, parent_link, group, elem.get("parent_group")))
    virtual = [e.get("name") for e in root.findall("virtual_joint") if e.get("name")]
    return Srdf(root.get("name", ""), groups, eefs, file, virtual)


def _check_subgroups(groups: dict[str, PlanningGroup], file: str) -> None:
    for group in groups.values():
        for sub in group.subgroups:
            if sub not in groups:
                raise TransferError(f"unknown subgroup {sub!r}", file, f"group {group.name!r}")


def srdf_from_data(data: dict, file: str) -> Srdf:
    """The ``Srdf`` of our groups file (``robot_data.load_groups``), checked as an SRDF is."""
    groups = {name: PlanningGroup(name, g["joints"], g["links"], g["chains"], g["subgroups"])
              for name, g in data["groups"].items()}
    _check_subgroups(groups, file)
    eefs = []
    for e in data["end_effectors"]:
        if e["group"] not in groups:
            raise TransferError(f"unknown group {e['group']!r}", file, f"end_effector {e['name']!r}")
        eefs.append(EndEffector(e["name"], e["parent_link"], e["group"], e["parent_group"]))
    return Srdf(data["robot"], groups, eefs, file, list(data["virtual_joints"]))


def _line(text: str, elem) -> str:
    needle = f'name="{elem.get("name")}"'
    index = text.find(needle)
    return str(text.count("\n", 0, index) + 1) if index >= 0 else "?"


def load_srdf(path: str | Path) -> Srdf:
    """Read an SRDF file (UTF-8 text, well-formed XML, consistent groups) or our groups file (``.yaml``)."""
    if is_robot_data(path):
        return srdf_from_data(load_groups(path), str(path))
    return parse_srdf(read_text(path, "SRDF file"), str(path))


def check_against_urdf(srdf: Srdf, urdf) -> None:
    """Every joint and link the SRDF names must exist in the URDF (inconsistent files are an error)."""
    for group in srdf.groups.values():
        for joint in group.joints:
            if not urdf.has_joint(joint) and joint not in srdf.virtual_joints:
                raise TransferError(f"joint {joint!r} is not in the URDF {urdf.file}", srdf.file,
                                    f"group {group.name!r}")
        for link in group.links + [x for chain in group.chains for x in chain]:
            if not urdf.has_link(link):
                raise TransferError(f"link {link!r} is not in the URDF {urdf.file}", srdf.file,
                                    f"group {group.name!r}")
    for eef in srdf.end_effectors:
        if not urdf.has_link(eef.parent_link):
            raise TransferError(f"link {eef.parent_link!r} is not in the URDF {urdf.file}", srdf.file,
                                f"end_effector {eef.name!r}")


def similarity(a: str, b: str) -> float:
    """Ratcliff-Obershelp (gestalt pattern matching) similarity, as difflib computes it."""
    return difflib.SequenceMatcher(None, a, b).ratio()


def rank_groups(source_group: str, srdf: Srdf) -> list[tuple[str, float]]:
    """Target planning groups, most similar name to the source group first (A.3)."""
    ranked = [(name, similarity(source_group, name)) for name in srdf.groups]
    return sorted(ranked, key=lambda item: (-item[1], item[0]))
