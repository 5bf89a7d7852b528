"""Find every communication channel of a program (thesis §2.5.1) with Python's ``ast``.

Recognised: ``rospy.Publisher``/``rospy.Subscriber`` (topic and type, positional or keyword),
``actionlib.SimpleActionClient``/``SimpleActionServer``, MoveIt's ``MoveGroupInterface`` (moveit_python)
and ``moveit_commander.MoveGroupCommander`` group names, and the pose frames given to ``moveToPose``,
``set_pose_target``, ``set_position_target`` and ``set_end_effector_link``. Names may be string literals
or variables bound to one literal; ``from ... import`` aliases are resolved.
"""
from __future__ import annotations

import ast
from dataclasses import dataclass

from ltl_stack.inputs import load_yaml

from .errors import TransferError
from .source_ast import SourceFile, Span, call_argument, string_value

TOPIC_CALLS = {"rospy.Publisher": "publisher", "rospy.Subscriber": "subscriber",
               "rospy.topics.Publisher": "publisher", "rospy.topics.Subscriber": "subscriber"}
ACTION_CALLS = {"actionlib.SimpleActionClient": "action_client",
                "actionlib.SimpleActionServer": "action_server",
                "actionlib.simple_action_client.SimpleActionClient": "action_client",
                "actionlib.simple_action_server.SimpleActionServer": "action_server"}
GROUP_CALLS = ("MoveGroupInterface", "MoveGroupCommander")
# method name -> (position, keyword) of its pose-frame argument
FRAME_METHODS = {"moveToPose": (1, "gripper_frame"), "set_pose_target": (1, "end_effector_link"),
                 "set_position_target": (1, "end_effector_link"),
                 "set_end_effector_link": (0, "link_name")}
KIND_WORDS = {"publisher": "topic", "subscriber": "topic", "action_client": "action",
              "action_server": "action", "move_group": "MoveIt group", "pose_frame": "pose frame"}


@dataclass
class NameRef:
    """A channel's name: a literal (maybe through a variable), or why it cannot be resolved."""

    value: str | None
    via: str | None = None            # variable name when bound through one
    problem: str | None = None        # why it cannot be resolved


@dataclass
class ChannelUse:
    """One channel the program opens: what kind, its name and its message/action type."""

    kind: str            # publisher | subscriber | action_client | action_server | move_group | pose_frame
    name: NameRef
    msg_type: str | None  # 'geometry_msgs/Twist', 'control_msgs/FollowJointTrajectoryAction', or None
    line: int

    @property
    def word(self) -> str:
        return KIND_WORDS[self.kind]


def resolve_name(src: SourceFile, node: ast.expr | None) -> NameRef:
    """A string literal, or a variable bound (only) to one string literal in its scope."""
    if node is None:
        return NameRef(None, problem="no name argument")
    text = string_value(node)
    if text is not None:
        return NameRef(text)
    if isinstance(node, ast.Name):
        values = src.bindings(node)
        literals = {string_value(v) for v in values}
        if values and None not in literals and len(literals) == 1:
            return NameRef(literals.pop(), via=node.id)  # every binding gets the same edit
        if not values:
            return NameRef(None, problem=f"variable {node.id!r} is not bound to a string literal here")
        return NameRef(None, problem=f"variable {node.id!r} is bound to a computed or varying value")
    return NameRef(None, problem=f"computed name {src.segment(node)!r}")


def name_spans(src: SourceFile, node: ast.expr | None) -> list[Span]:
    """Every literal that a change of this name must edit (all bindings of the variable)."""
    if node is None:
        return []
    if string_value(node) is not None:
        return [src.span(node)]
    if isinstance(node, ast.Name):
        return [src.span(v) for v in src.bindings(node) if string_value(v) is not None]
    return []


def message_type(src: SourceFile, node: ast.expr | None) -> str | None:
    """``geometry_msgs.msg.Twist`` -> ``geometry_msgs/Twist``; a bare unresolved ``Twist`` stays ``Twist``."""
    if node is None:
        return None
    name = src.qualname(node)
    if name is None:
        return None
    parts = name.split(".")
    if len(parts) >= 3 and parts[-2] == "msg":
        return f"{parts[-3]}/{parts[-1]}"
    return parts[-1]


@dataclass
class ChannelSite:
    """A channel use together with the AST node of its name argument (for the rewriter)."""

    use: ChannelUse
    name_node: ast.expr | None


def find_channel_sites(src: SourceFile) -> list[ChannelSite]:
    """All channel uses in source order."""
    sites: list[ChannelSite] = []
    has_group = False
    for node in ast.walk(src.tree):
        if not isinstance(node, ast.Call):
            continue
        callee = src.qualname(node.func) or ""
        kind = TOPIC_CALLS.get(callee)
        if kind:
            name_node = call_argument(node, 0, "name")
            type_node = call_argument(node, 1, "data_class")
        elif callee in ACTION_CALLS:
            kind = ACTION_CALLS[callee]
            name_node = call_argument(node, 0, "ns" if kind == "action_client" else "name")
            type_node = call_argument(node, 1, "ActionSpec")
        elif callee.split(".")[-1] in GROUP_CALLS:
            kind, has_group = "move_group", True
            name_node = call_argument(node, 0, "group" if callee.endswith("Interface") else "name")
            type_node = None
        elif isinstance(node.func, ast.Attribute) and node.func.attr in FRAME_METHODS:
            kind = "pose_frame"
            name_node = call_argument(node, *FRAME_METHODS[node.func.attr])
            type_node = None
            if name_node is None:
                continue
        else:
            continue
        use = ChannelUse(kind, resolve_name(src, name_node), message_type(src, type_node), node.lineno)
        sites.append(ChannelSite(use, name_node))
    if not has_group:
        sites = [s for s in sites if s.use.kind != "pose_frame"]
    sites.sort(key=lambda s: (s.use.line, s.use.kind))
    return sites


def find_channels(text: str, filename: str = "<source>") -> list[ChannelUse]:
    """Channel uses of a program given as text."""
    return [site.use for site in find_channel_sites(SourceFile(text, filename))]


def actions_from_topics(topics: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """Actions (name, 'pkg/XAction') implied by a topic table: ``ns/goal`` of type ``pkg/XActionGoal``
    with ``ns/status`` and ``ns/result`` beside it (an action is listed once, as ``ns``)."""
    by_name = dict(topics)
    actions = []
    for name, msg_type in topics:
        if name.endswith("/goal") and msg_type.endswith("ActionGoal"):
            ns = name[: -len("/goal")]
            if all(f"{ns}/{suffix}" in by_name for suffix in ("status", "result")):
                actions.append((ns, msg_type[: -len("Goal")]))
    return sorted(actions)


def channel_listing(topics: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """The A.2 listing of a master's topic table: every topic, then every action it implies."""
    return sorted(topics) + actions_from_topics(topics)


def load_listing(path: str) -> list[tuple[str, str]]:
    """An A.2 listing saved from the target's master: YAML ``name: type`` per topic (as ``rostopic list
    -v`` shows them; an action may be given by its five topics or as ``ns: pkg/XAction``)."""
    data = load_yaml(path, "channel listing")
    if not isinstance(data, dict):
        raise TransferError("expected a mapping of channel name -> message type", str(path))
    for name, msg_type in data.items():
        if not isinstance(msg_type, str) or "/" not in msg_type:
            raise TransferError(f"the type of {name!r} must be 'package/Type', got {msg_type!r}", str(path))
    return channel_listing(list(data.items()))
