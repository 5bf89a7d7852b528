"""Command-line nodes for looking at and setting proposition valuations by hand.

``set_propositions TOPIC a=1,b=0`` publishes one valuation (latched) and, with ``--rate``, keeps
publishing it; ``proposition_monitor TOPIC`` prints every valuation it receives, readable or as
JSON lines. Both are ordinary rospy nodes: they need a running master.
"""
from __future__ import annotations

import argparse
import json
import sys
import time

import rosgraph
import rospy

from ltl_stack.msg import PropositionValuation
from ltl_stack.ros.valuation import msg_to_valuation, valuation_to_msg
from ltl_stack.spec.valuation import format_valuation, parse_valuation

EXIT_OK, EXIT_BAD_INPUT, EXIT_NO_MASTER = 0, 2, 3


def wait_for_master(timeout: float) -> bool:
    """True once the master at $ROS_MASTER_URI answers, False after ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if rosgraph.is_master_online():
            return True
        time.sleep(0.1)
    return False


def set_propositions_main(argv: list[str] | None = None) -> int:
    """Entry point of ``set_propositions``."""
    parser = argparse.ArgumentParser(
        prog="set_propositions",
        description="Publish a proposition valuation (ltl_stack/PropositionValuation) on a topic.",
        epilog="Exit codes: 0 published, 2 bad valuation, 3 no ROS master.")
    parser.add_argument("topic", help="topic to publish on, e.g. /simple/valuation")
    parser.add_argument("valuation", help="e.g. 'person=1,move=0' or 'person !move'")
    parser.add_argument("--rate", type=float, default=0.0,
                        help="keep publishing at this rate (Hz) until interrupted; default: once")
    parser.add_argument("--wait-subscribers", type=int, default=0, metavar="N",
                        help="wait until N subscribers are connected before publishing")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds to wait for master/subscribers")
    parser.add_argument("--json", action="store_true", help="print what was published as JSON")
    args = parser.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    try:
        valuation = parse_valuation(args.valuation.replace(" ", ","))
    except ValueError as err:
        print(f"set_propositions: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    if not wait_for_master(args.timeout):
        print("set_propositions: no ROS master at $ROS_MASTER_URI", file=sys.stderr)
        return EXIT_NO_MASTER
    rospy.init_node("set_propositions", anonymous=True, disable_signals=False)
    pub = rospy.Publisher(args.topic, PropositionValuation, queue_size=1, latch=True)
    deadline = rospy.Time.now() + rospy.Duration(args.timeout)
    while pub.get_num_connections() < args.wait_subscribers and not rospy.is_shutdown():
        if rospy.Time.now() > deadline:
            print(f"set_propositions: fewer than {args.wait_subscribers} subscribers on {args.topic}",
                  file=sys.stderr)
            return EXIT_NO_MASTER
        rospy.sleep(0.02)
    pub.publish(valuation_to_msg(valuation))
    if args.json:
        print(json.dumps({"topic": args.topic, "valuation": valuation}), flush=True)
    else:
        print(f"{args.topic}: {format_valuation(valuation)}", flush=True)
    if args.rate > 0:
        rate = rospy.Rate(args.rate)
        while not rospy.is_shutdown():
            pub.publish(valuation_to_msg(valuation))
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
    else:
        # Latched: stay up briefly so late subscribers that are already connecting get it.
        rospy.sleep(0.5)
    return EXIT_OK


def proposition_monitor_main(argv: list[str] | None = None) -> int:
    """Entry point of ``proposition_monitor``."""
    parser = argparse.ArgumentParser(
        prog="proposition_monitor",
        description="Print every proposition valuation received on a topic.",
        epilog="Exit codes: 0 done, 3 no ROS master.")
    parser.add_argument("topic", help="topic of ltl_stack/PropositionValuation messages")
    parser.add_argument("--count", type=int, default=0, help="exit after this many messages (0: never)")
    parser.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds to wait for the master")
    args = parser.parse_args(rospy.myargv(argv if argv is not None else sys.argv)[1:])
    if not wait_for_master(args.timeout):
        print("proposition_monitor: no ROS master at $ROS_MASTER_URI", file=sys.stderr)
        return EXIT_NO_MASTER
    rospy.init_node("proposition_monitor", anonymous=True)
    received = 0

    def on_valuation(msg: PropositionValuation) -> None:
        nonlocal received
        try:
            valuation = msg_to_valuation(msg)
        except ValueError as err:
            rospy.logwarn("%s: %s", args.topic, err)
            return
        received += 1
        stamp = msg.header.stamp.to_sec()
        if args.json:
            print(json.dumps({"topic": args.topic, "stamp": stamp, "valuation": valuation}), flush=True)
        else:
            print(f"[{stamp:.3f}] {args.topic}: {format_valuation(valuation)}", flush=True)
        if args.count and received >= args.count:
            rospy.signal_shutdown("received enough messages")

    rospy.Subscriber(args.topic, PropositionValuation, on_valuation)
    rospy.loginfo("proposition_monitor listening on %s", rospy.resolve_name(args.topic))
    rospy.spin()
    return EXIT_OK
