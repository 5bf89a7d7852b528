#!/usr/bin/env python3
"""Test graphs described in YAML: as a snapshot (unit tests) or as real rospy nodes (integration tests).

A scenario file (see clean_and_patrol.yaml) lists nodes with the topics they publish (``pub``) and
subscribe (``sub``), and the action namespaces they are clients or servers of. Every action is an
``ltl_stack/Proposition`` action; topics are ``std_msgs/Bool`` unless ``topic_types`` says otherwise.

    python scenario_graph.py SCENARIO NODE     # run NODE of SCENARIO as a real ROS node until killed

``scenario_snapshot`` builds the snapshot that the master would report for the running scenario
(including rospy's own ``/rosout`` publication and logger services), so a unit test and a live
test of the same scenario expect the same findings.
"""
from __future__ import annotations

import sys
from pathlib import Path

import yaml

ACTION_TYPE = "ltl_stack/Proposition"
DEFAULT_TYPE = "std_msgs/Bool"


def load_scenario(path: str | Path) -> dict:
    return normalised(yaml.safe_load(Path(path).read_text()))


def normalised(data: dict) -> dict:
    """Fill in the optional keys of a scenario (also for scenarios written inline in tests)."""
    data.setdefault("topic_types", {})
    for spec in data["nodes"].values():
        for key in ("pub", "sub", "clients", "servers"):
            spec.setdefault(key, [])
    return data


def topic_type(scenario: dict, topic: str) -> str:
    """The message type of ``topic``; the five topics of a scenario action get actionlib's types."""
    ns, _, suffix = topic.rpartition("/")
    actions = {a for spec in scenario["nodes"].values() for a in (*spec["clients"], *spec["servers"])}
    if ns in actions:
        return {"goal": ACTION_TYPE + "ActionGoal", "feedback": ACTION_TYPE + "ActionFeedback",
                "result": ACTION_TYPE + "ActionResult", "status": "actionlib_msgs/GoalStatusArray",
                "cancel": "actionlib_msgs/GoalID"}.get(suffix, DEFAULT_TYPE)
    return scenario["topic_types"].get(topic, DEFAULT_TYPE)


def scenario_snapshot(path: str | Path):
    """The ``Snapshot`` a master holds while every node of the scenario file runs."""
    return snapshot_of(load_scenario(path), master="scenario:" + Path(path).name)


def snapshot_of(scenario: dict, master: str = "scenario"):
    """The ``Snapshot`` of a scenario given as data (``{"nodes": {name: {pub, sub, clients, servers}}}``)."""
    from ltl_stack.analysis.snapshot import Snapshot

    scenario = normalised(scenario)
    pubs: dict[str, set[str]] = {}
    subs: dict[str, set[str]] = {}
    types: dict[str, str] = {}
    services = {}
    for node, spec in scenario["nodes"].items():
        for t in [*spec["pub"], "/rosout"]:
            pubs.setdefault(t, set()).add(node)
            types[t] = "rosgraph_msgs/Log" if t == "/rosout" else topic_type(scenario, t)
        for t in spec["sub"]:
            subs.setdefault(t, set()).add(node)
            types[t] = topic_type(scenario, t)
        for role, mine, theirs in (("clients", ("goal", "cancel"), ("status", "feedback", "result")),
                                   ("servers", ("status", "feedback", "result"), ("goal", "cancel"))):
            for ns in spec[role]:
                for suffix in mine:
                    pubs.setdefault(f"{ns}/{suffix}", set()).add(node)
                for suffix in theirs:
                    subs.setdefault(f"{ns}/{suffix}", set()).add(node)
                for suffix in (*mine, *theirs):
                    types[f"{ns}/{suffix}"] = topic_type(scenario, f"{ns}/{suffix}")
        for srv in ("get_loggers", "set_logger_level"):
            services[f"{node}/{srv}"] = [node]
    return Snapshot.from_system_state(
        [(t, sorted(n)) for t, n in pubs.items()], [(t, sorted(n)) for t, n in subs.items()],
        [(s, n) for s, n in services.items()], [(t, ty) for t, ty in types.items() if t in pubs or t in subs],
        master=master)


def expected_registrations(path: str | Path) -> set[tuple[str, str, str]]:
    """(``pub``|``sub``, topic, node) triples the master must list before the scenario is fully up."""
    snap = scenario_snapshot(path)
    found = set()
    for name, t in snap.topics.items():
        found.update(("pub", name, n) for n in t.publishers)
        found.update(("sub", name, n) for n in t.subscribers)
    return found


def run_node(path: str, node: str) -> None:
    scenario = load_scenario(path)
    spec = scenario["nodes"][node]
    namespace, _, name = node.rpartition("/")
    sys.argv = [sys.argv[0], f"__ns:={namespace or '/'}"]  # rospy takes the namespace from sys.argv
    import ltl_stack.ros  # noqa: F401, I001 - first, as in our nodes: start-up and shutdown fixes
    import actionlib
    import roslib.message
    import rospy

    from ltl_stack.msg import PropositionAction

    rospy.init_node(name, anonymous=False)
    keep = []
    for t in spec["pub"]:
        keep.append(rospy.Publisher(t, roslib.message.get_message_class(topic_type(scenario, t)), queue_size=1))
    for t in spec["sub"]:
        keep.append(rospy.Subscriber(t, roslib.message.get_message_class(topic_type(scenario, t)), lambda _: None))
    for ns in spec["servers"]:
        server = actionlib.SimpleActionServer(ns, PropositionAction, auto_start=False)
        server.start()
        keep.append(server)
    for ns in spec["clients"]:
        keep.append(actionlib.SimpleActionClient(ns, PropositionAction))
    rospy.loginfo("scenario node %s up", node)
    rospy.spin()


if __name__ == "__main__":
    run_node(sys.argv[1], sys.argv[2])
