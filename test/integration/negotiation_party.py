"""One negotiating robot as a ROS node, for the negotiation transport tests (no executor node):
``python negotiation_party.py ROLE SPEC MAPPING [--peer P] [--timeout S] [--inputs JSON] [--outputs JSON]``.

ROLE ``responder`` serves ``~negotiate`` around a ``Controller`` over a ``ResilientStrategy``;
``initiator`` also negotiates once with ``--peer`` from the given position and prints the report;
``silent`` offers a ``~negotiate`` service that never answers. ``--start`` gives the controller's first
readings when they differ from the position the initiator negotiates from (so that it answers too). Every report is printed as one JSON
line ``{"report": …}``; an adopted spec as ``{"adopted": robot}``.
"""
from __future__ import annotations

import argparse
import json
import sys
import threading
import time

import rospy

from ltl_stack.ros.negotiation import NegotiationEndpoint
from ltl_stack.runtime.config.mapping import load_mapping
from ltl_stack.runtime.executor.controller import Controller
from ltl_stack.runtime.resilience.characterize import ResilientStrategy
from ltl_stack.runtime.resilience.negotiation import Negotiator, classes_authenticator, classes_from_mapping
from ltl_stack.spec import load_spec
from ltl_stack.srv import Negotiate


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("role", choices=["responder", "initiator", "silent"])
    parser.add_argument("spec")
    parser.add_argument("mapping")
    parser.add_argument("--peer")
    parser.add_argument("--timeout", type=float, default=5.0)
    parser.add_argument("--inputs", default="{}")
    parser.add_argument("--outputs", default="{}")
    parser.add_argument("--adopted", help="where an adopted spec is written (two-phase; default: nowhere)")
    parser.add_argument("--start", help="the controller's first readings (JSON; default: --inputs)")
    args = parser.parse_args(rospy.myargv(sys.argv)[1:])
    rospy.init_node("controller_executor")
    if args.role == "silent":
        rospy.Service("~negotiate", Negotiate, lambda _request: time.sleep(3600))
        print(json.dumps({"ready": rospy.get_name()}), flush=True)
        rospy.spin()
        return 0
    spec = load_spec(args.spec)
    classes = classes_from_mapping(load_mapping(args.mapping))
    strategy = ResilientStrategy(spec, recovery=False)
    controller = Controller(strategy, settle_steps=0)
    inputs = {**dict.fromkeys(spec.inputs, False), **json.loads(args.inputs)}
    controller.report_many({**dict.fromkeys(spec.inputs, False), **json.loads(args.start)} if args.start else inputs)
    negotiator = Negotiator(classes, path=args.adopted)

    lock = threading.Lock()  # two negotiations can end at once, in two threads: lines stay whole

    def report(n) -> None:
        if n.done:
            with lock:
                print(json.dumps({"report": n.report()}), flush=True)
                if n.adopted is not None:
                    print(json.dumps({"adopted": classes.robot, "running": controller.current_outputs()}), flush=True)

    NegotiationEndpoint(negotiator, strategy, controller, timeout=args.timeout, on_report=report,
                        auth=classes_authenticator(classes))
    print(json.dumps({"ready": rospy.get_name()}), flush=True)
    if args.role == "initiator":
        outputs = {**dict.fromkeys(spec.outputs, False), **json.loads(args.outputs)}
        negotiator.initiate(strategy.characterizer.original, args.peer, inputs, outputs)
    rospy.spin()
    return 0


if __name__ == "__main__":
    sys.exit(main())
