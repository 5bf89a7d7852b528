"""Find every communication channel of a program (thesis §2.5.1) with Python's ``ast``.

Recognised (``CHANNEL_CALLS``): ``rospy.Publisher``/``Subscriber``/``wait_for_message``,
``message_filters.Subscriber``, ``rospy.ServiceProxy``/``Service``/``wait_for_service``,
``actionlib.SimpleActionClient``/``SimpleActionServer``; tf/tf2 frames (``TF_FRAME_METHODS``, and
``header.frame_id``/``child_frame_id`` assignments); MoveIt groups and pose frames (see ``moveit.py``).
A name is followed through variables, ``self.<attr>`` assignments, ``rospy.get_param`` defaults,
import aliases, type aliases (``TwistMsg = Twist``) and the parameters of a wrapper function (one
channel per call of the wrapper). What cannot be followed carries the reason (``NameRef.problem``).
"""
from __future__ import annotations

import ast
from dataclasses import dataclass

from ltl_stack.inputs import load_yaml

from .errors import TransferError
from .moveit import find_moveit_uses
from .names import NameRef, Subst, call_contexts, resolve_name
from .source_ast import SourceFile, Span, call_argument

# qualified call -> (kind, (position, keyword) of the name, (position, keyword) of the type or None)
_TOPIC = ((0, "name"), (1, "data_class"))
CHANNEL_CALLS = {
    "rospy.Publisher": ("publisher", *_TOPIC), "rospy.topics.Publisher": ("publisher", *_TOPIC),
    "rospy.Subscriber": ("subscriber", *_TOPIC), "rospy.topics.Subscriber": ("subscriber", *_TOPIC),
    "message_filters.Subscriber": ("subscriber", *_TOPIC),
    "rospy.wait_for_message": ("wait_for_message", (0, "topic"), (1, "topic_type")),
    "rospy.client.wait_for_message": ("wait_for_message", (0, "topic"), (1, "topic_type")),
    "rospy.ServiceProxy": ("service_client", (0, "name"), (1, "service_class")),
    "rospy.impl.tcpros_service.ServiceProxy": ("service_client", (0, "name"), (1, "service_class")),
    "rospy.Service": ("service_server", (0, "name"), (1, "service_class")),
    "rospy.impl.tcpros_service.Service": ("service_server", (0, "name"), (1, "service_class")),
    "rospy.wait_for_service": ("service_wait", (0, "service"), None),
    "rospy.impl.tcpros_service.wait_for_service": ("service_wait", (0, "service"), None),
    "actionlib.SimpleActionClient": ("action_client", (0, "ns"), (1, "ActionSpec")),
    "actionlib.simple_action_client.SimpleActionClient": ("action_client", (0, "ns"), (1, "ActionSpec")),
    "actionlib.SimpleActionServer": ("action_server", (0, "name"), (1, "ActionSpec")),
    "actionlib.simple_action_server.SimpleActionServer": ("action_server", (0, "name"), (1, "ActionSpec")),
}
#: tf (``TransformListener``) and tf2 (``Buffer``) methods -> (position, keyword) of each frame argument
TF_FRAME_METHODS = {
    "lookup_transform": ((0, "target_frame"), (1, "source_frame")),
    "can_transform": ((0, "target_frame"), (1, "source_frame")),
    "lookupTransform": ((0, "target_frame"), (1, "source_frame")),
    "canTransform": ((0, "target_frame"), (1, "source_frame")),
    "waitForTransform": ((0, "target_frame"), (1, "source_frame")),
    "sendTransform": ((3, "child"), (4, "parent")),
}
#: frames a program broadcasts itself (they exist wherever it runs)
OWN_FRAME_ARGUMENTS = {("sendTransform", "child")}
FRAME_FIELDS = ("frame_id", "child_frame_id")
#: calls that open channels in APIs this tool does not transfer: listed as unresolved, never passed over
UNFOLLOWED_APIS = {"create_publisher": "ROS 2", "create_subscription": "ROS 2", "create_client": "ROS 2",
                   "create_service": "ROS 2", "ActionClient": "ROS 2 / actionlib ActionClient",
                   "ActionServer": "actionlib ActionServer", "Publisher": None, "Subscriber": None,
                   "ServiceProxy": None, "SimpleActionClient": None, "SimpleActionServer": None}
KIND_WORDS = {"publisher": "topic", "subscriber": "topic", "wait_for_message": "topic",
              "service_client": "service", "service_server": "service", "service_wait": "service",
              "action_client": "action", "action_server": "action", "move_group": "MoveIt group",
              "pose_frame": "pose frame", "frame": "tf frame", "own_frame": "tf frame",
              "unknown_api": "channel", "ee_group": "MoveIt end-effector group", "joint": "joint",
              "named_state": "MoveIt named state"}
NAMED_KINDS = ("publisher", "subscriber", "wait_for_message", "service_client", "service_server",
               "service_wait", "action_client", "action_server")


@dataclass
class ChannelUse:
    """One channel the program opens: what kind, its name and its message/action type."""

    kind: str            # a key of KIND_WORDS
    name: NameRef
    msg_type: str | None  # 'geometry_msgs/Twist', 'control_msgs/FollowJointTrajectoryAction', or None
    line: int

    @property
    def word(self) -> str:
        return KIND_WORDS[self.kind]


def message_type(src: SourceFile, node: ast.expr | None, subst: Subst | None = None) -> str | None:
    """``geometry_msgs.msg.Twist`` -> ``geometry_msgs/Twist`` (also ``.srv``); a bare unresolved ``Twist``
    stays ``Twist``; type aliases (``TwistMsg = Twist``) give their first binding."""
    if node is None:
        return None
    if subst and isinstance(node, ast.Name) and node.id in subst:
        node = subst[node.id]
        if node is None:
            return None
    name = src.qualname(node)
    if name is None:
        return None
    parts = name.split(".")
    if len(parts) >= 3 and parts[-2] in ("msg", "srv"):
        return f"{parts[-3]}/{parts[-1]}"
    return parts[-1]


@dataclass
class ChannelSite:
    """A channel use with the call that opens it (None for an assigned frame field)."""

    use: ChannelUse
    call: ast.Call | None = None

    @property
    def spans(self) -> list[Span]:
        return self.use.name.spans


def find_channel_sites(src: SourceFile) -> list[ChannelSite]:
    """All channel uses in source order (one per call of a wrapper function)."""
    sites: list[ChannelSite] = []
    for node in ast.walk(src.tree):
        if isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Attribute) and target.attr in FRAME_FIELDS:
                    kind = "own_frame" if target.attr == "child_frame_id" else "frame"
                    for subst, line in call_contexts(src, node, [node.value]):
                        sites.append(ChannelSite(ChannelUse(kind, resolve_name(src, node.value, subst), None,
                                                            line or node.lineno)))
            continue
        if not isinstance(node, ast.Call):
            continue
        callee = src.qualname(node.func) or ""
        if callee in CHANNEL_CALLS:
            kind, name_at, type_at = CHANNEL_CALLS[callee]
            name_node = call_argument(node, *name_at)
            type_node = call_argument(node, *type_at) if type_at else None
            for subst, line in call_contexts(src, node, [name_node, type_node]):
                use = ChannelUse(kind, resolve_name(src, name_node, subst), message_type(src, type_node, subst),
                                 line or node.lineno)
                sites.append(ChannelSite(use, node))
        elif isinstance(node.func, ast.Attribute) and node.func.attr in TF_FRAME_METHODS \
                and not callee.startswith(("rospy.", "actionlib.")):
            for at in TF_FRAME_METHODS[node.func.attr]:
                frame_node = call_argument(node, *at)
                if frame_node is None:
                    continue
                kind = "own_frame" if (node.func.attr, at[1]) in OWN_FRAME_ARGUMENTS else "frame"
                for subst, line in call_contexts(src, node, [frame_node]):
                    sites.append(ChannelSite(ChannelUse(kind, resolve_name(src, frame_node, subst), None,
                                                        line or node.lineno), node))
        else:
            last = callee.split(".")[-1] if callee else getattr(node.func, "attr", "")
            if last in UNFOLLOWED_APIS:
                api = UNFOLLOWED_APIS[last] or "an API this tool does not know"
                problem = f"{src.segment(node.func)}(...) is {api}; its channel is not followed"
                sites.append(ChannelSite(ChannelUse("unknown_api", NameRef(None, problem=problem), None,
                                                    node.lineno), node))
    sites += [ChannelSite(ChannelUse(kind, ref, None, line), call) for kind, ref, line, call in find_moveit_uses(src)]
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
