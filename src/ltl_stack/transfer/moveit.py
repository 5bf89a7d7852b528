"""MoveIt's Python APIs in a program (thesis §2.5.1, A.3): groups, end effectors, frames and joints.

* groups: ``MoveGroupInterface`` and ``PickPlaceInterface`` (moveit_python), ``MoveGroupCommander``
  (moveit_commander);
* end-effector groups: ``PickPlaceInterface``'s second argument;
* pose frames: the frames given to ``moveToPose``, ``set_pose_target``, ``set_position_target`` and
  ``set_end_effector_link`` (only in a program that opens a group);
* frames: moveit_python's ``PlanningSceneInterface(frame)``;
* joint names: the keys of ``set_joint_value_target({...})`` and ``set_joint_value_target(name, value)``
  (``moveToJointPosition``'s names and positions are joint arrays: ``commands.py``);
* named states: ``set_named_target(name)`` (an SRDF ``group_state`` of the source).
"""
from __future__ import annotations

import ast

from .names import NameRef, call_contexts, resolve_name
from .source_ast import SourceFile, call_argument

GROUP_CALLS = {"MoveGroupInterface": (0, "group"), "MoveGroupCommander": (0, "name"),
               "PickPlaceInterface": (0, "group")}
# method name -> (position, keyword) of its pose-frame argument
FRAME_METHODS = {"moveToPose": (1, "gripper_frame"), "set_pose_target": (1, "end_effector_link"),
                 "set_position_target": (1, "end_effector_link"),
                 "set_end_effector_link": (0, "link_name")}


def find_moveit_uses(src: SourceFile) -> list[tuple[str, NameRef, int, ast.Call]]:
    """MoveIt uses (kind, name, line, call), one per call of a wrapper function."""
    sites: list[tuple[str, NameRef, int, ast.Call]] = []
    has_group = False
    for node in ast.walk(src.tree):
        if not isinstance(node, ast.Call):
            continue
        callee = src.qualname(node.func) or ""
        last = callee.split(".")[-1]
        found: list[tuple[str, ast.expr | None]] = []
        if last in GROUP_CALLS:
            has_group = True
            found.append(("move_group", call_argument(node, *GROUP_CALLS[last])))
            if last == "PickPlaceInterface":
                found.append(("ee_group", call_argument(node, 1, "ee_group")))
        elif callee == "moveit_python.PlanningSceneInterface":
            found.append(("frame", call_argument(node, 0, "frame")))
        elif isinstance(node.func, ast.Attribute) and node.func.attr in FRAME_METHODS:
            found.append(("pose_frame", call_argument(node, *FRAME_METHODS[node.func.attr])))
        elif isinstance(node.func, ast.Attribute) and node.func.attr == "set_named_target":
            found.append(("named_state", call_argument(node, 0, "name")))
        elif isinstance(node.func, ast.Attribute) and node.func.attr == "set_joint_value_target" and node.args:
            first = node.args[0]
            if isinstance(first, ast.Dict):
                found += [("joint", key) for key in first.keys if key is not None]
            elif len(node.args) == 2:
                found.append(("joint", first))
        for kind, name_node in found:
            if name_node is None:
                continue
            for subst, line in call_contexts(src, node, [name_node]):
                sites.append((kind, resolve_name(src, name_node, subst), line or node.lineno, node))
    if not has_group:
        sites = [s for s in sites if s[0] not in ("pose_frame", "named_state")]
    return sites
