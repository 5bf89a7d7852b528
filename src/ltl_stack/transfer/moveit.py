"""MoveIt's Python APIs in a program (thesis §2.5.1, A.3): planning groups and pose frames.

Groups: ``MoveGroupInterface`` (moveit_python) and ``moveit_commander.MoveGroupCommander``. Pose
frames: the frames given to ``moveToPose``, ``set_pose_target``, ``set_position_target`` and
``set_end_effector_link`` (only in a program that opens a group).
"""
from __future__ import annotations

import ast

from .names import NameRef, call_contexts, resolve_name
from .source_ast import SourceFile, call_argument

GROUP_CALLS = {"MoveGroupInterface": (0, "group"), "MoveGroupCommander": (0, "name")}
# method name -> (position, keyword) of its pose-frame argument
FRAME_METHODS = {"moveToPose": (1, "gripper_frame"), "set_pose_target": (1, "end_effector_link"),
                 "set_position_target": (1, "end_effector_link"),
                 "set_end_effector_link": (0, "link_name")}


def find_moveit_uses(src: SourceFile) -> list[tuple[str, NameRef, int, ast.Call]]:
    """MoveIt group and pose-frame uses (kind, name, line, call), one per call of a wrapper function."""
    sites: list[tuple[str, NameRef, int, ast.Call]] = []
    has_group = False
    for node in ast.walk(src.tree):
        if not isinstance(node, ast.Call):
            continue
        last = (src.qualname(node.func) or "").split(".")[-1]
        if last in GROUP_CALLS:
            kind, has_group = "move_group", True
            name_node = call_argument(node, *GROUP_CALLS[last])
        elif isinstance(node.func, ast.Attribute) and node.func.attr in FRAME_METHODS:
            kind = "pose_frame"
            name_node = call_argument(node, *FRAME_METHODS[node.func.attr])
            if name_node is None:
                continue
        else:
            continue
        for subst, line in call_contexts(src, node, [name_node]):
            sites.append((kind, resolve_name(src, name_node, subst), line or node.lineno, node))
    if not has_group:
        sites = [s for s in sites if s[0] != "pose_frame"]
    return sites
