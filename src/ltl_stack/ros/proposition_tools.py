"""Command-line nodes for looking at and setting proposition valuations by hand.

``set_propositions TOPIC a=1,b=0`` publishes one valuation (latched) and, with ``--rate``, keeps
publishing it; ``proposition_monitor TOPIC`` prints every valuation it receives, readable or as
JSON lines. Both are ordinary rospy nodes: they need a running master (``--master-uri``, else
``$ROS_MASTER_URI``). A malformed master URI, an illegal topic name or a bad number is exit 2 with
one line; no master is exit 3 (``ltl_stack.errors.Exit``).
"""
from __future__ import annotations

import json
import sys

import rospy

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.msg import PropositionValuation
from ltl_stack.ros.master import init_node, master_uri, ros_name, wait_for_master
from ltl_stack.ros.valuation import msg_to_valuation, valuation_to_msg
from ltl_stack.spec.valuation import format_valuation, parse_valuation


def add_master_options(parser: cli.ToolParser, timeout: float = 10.0, what: str = "the master") -> None:
    """``--master-uri`` and ``--timeout`` as every tool that talks to a master has them."""
    parser.add_argument("--master-uri", metavar="URI",
                        help="the ROS master (default: __master:= or $ROS_MASTER_URI)")
    parser.add_argument("--timeout", type=cli.positive_float, default=timeout, metavar="S",
                        help=f"seconds to wait for {what} (default: %(default)s)")


def _argv(argv: list[str] | None) -> list[str]:
    return rospy.myargv(argv if argv is not None else sys.argv)[1:]


def set_propositions_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "set_propositions", "Publish a proposition valuation (ltl_stack/PropositionValuation) on a topic.",
        exit_codes=(Exit.OK, Exit.BAD_INPUT, Exit.NO_ROS))
    parser.add_argument("topic", type=ros_name, help="topic to publish on, e.g. /simple/valuation")
    parser.add_argument("valuation", help="e.g. 'person=1,move=0' or 'person !move'")
    parser.add_argument("--rate", type=cli.rate_or_zero, default=0.0, metavar="HZ",
                        help="keep publishing at this rate (Hz, at most 1000) until interrupted; default 0: once")
    parser.add_argument("--wait-subscribers", type=cli.non_negative_int, default=0, metavar="N",
                        help="wait until N subscribers are connected before publishing")
    add_master_options(parser, what="the master and the subscribers")
    parser.add_json("what was published")
    return parser


def set_propositions_main(argv: list[str] | None = None) -> int:
    """Entry point of ``set_propositions``."""
    args = set_propositions_parser().parse_args(_argv(argv))
    return cli.run("set_propositions", lambda: _set_propositions(args))


def _set_propositions(args) -> int:
    try:
        valuation = parse_valuation(args.valuation.replace(" ", ","))
    except ValueError as err:
        raise UserError(str(err)) from None
    wait_for_master(master_uri(args.master_uri), args.timeout)
    init_node("set_propositions", anonymous=True, disable_signals=False)
    pub = rospy.Publisher(args.topic, PropositionValuation, queue_size=1, latch=True)
    deadline = rospy.Time.now() + rospy.Duration(args.timeout)
    while pub.get_num_connections() < args.wait_subscribers and not rospy.is_shutdown():
        if rospy.Time.now() > deadline:
            raise UserError(f"fewer than {args.wait_subscribers} subscribers on {args.topic} after "
                            f"{args.timeout:g} s", Exit.NO_ROS)
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
    return Exit.OK


def proposition_monitor_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "proposition_monitor", "Print every proposition valuation received on a topic.",
        exit_codes=(Exit.OK, Exit.BAD_INPUT, Exit.NO_ROS))
    parser.add_argument("topic", type=ros_name, help="topic of ltl_stack/PropositionValuation messages")
    parser.add_argument("--count", type=cli.non_negative_int, default=0,
                        help="exit after this many messages (default 0: never)")
    add_master_options(parser)
    parser.add_json("each valuation, one object per line,")
    return parser


def proposition_monitor_main(argv: list[str] | None = None) -> int:
    """Entry point of ``proposition_monitor``."""
    args = proposition_monitor_parser().parse_args(_argv(argv))
    return cli.run("proposition_monitor", lambda: _proposition_monitor(args))


def _proposition_monitor(args) -> int:
    wait_for_master(master_uri(args.master_uri), args.timeout)
    init_node("proposition_monitor", anonymous=True)
    received = 0

    def on_valuation(msg: PropositionValuation) -> None:
        nonlocal received
        try:
            valuation = msg_to_valuation(msg)
        except ValueError as err:
            cli.warn("proposition_monitor", f"{args.topic}: {err}")
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
    cli.say("proposition_monitor", f"listening on {rospy.resolve_name(args.topic)}")
    rospy.spin()
    return Exit.OK
