"""``check_run SPEC MAPPING BAG``: check a recorded run (a rosbag of the executor's ``~state``) against
the spec: per step whether the environment assumptions held (which clause broke, when), whether every
system guarantee held, how often each goal was reached (``ltl_stack.runtime.run_check``). No master
is needed: the bag is read from the file.

``read_states`` is also what ``controller_trace --bag`` replays.
"""
from __future__ import annotations

import sys
from pathlib import Path

from ltl_stack import cli
from ltl_stack.errors import Exit, InputError, UserError
from ltl_stack.runtime.trace import TraceStep

STATE_TYPE = "ltl_stack/ControllerState"


def read_states(bag_path: str, topic: str | None = None, namespace: str | None = None) -> tuple[str, list]:
    """(topic, messages) of the ControllerState topic in the bag: ``topic``, else the executor's of the
    scenario ``namespace``, else the only ControllerState topic the bag holds. InputError otherwise."""
    import rosbag

    path = Path(bag_path)
    if not path.is_file():
        raise InputError(bag_path, "no such bag file" if not path.exists() else "not a file")
    try:
        with rosbag.Bag(bag_path) as bag:
            topics = bag.get_type_and_topic_info().topics
            states = sorted(t for t, info in topics.items() if info.msg_type == STATE_TYPE)
            wanted = topic or (f"/{namespace.strip('/')}/controller_executor/state" if namespace else None)
            if wanted is not None and wanted not in states and topic is None and len(states) == 1:
                wanted = states[0]
            if wanted is None:
                if len(states) != 1:
                    raise InputError(bag_path, f"holds {len(states)} {STATE_TYPE} topics ({', '.join(states) or 'none'}):"
                                     " name one with --topic")
                wanted = states[0]
            if wanted not in states:
                raise InputError(bag_path, f"no {STATE_TYPE} messages on {wanted} (it has: {', '.join(states) or 'none'})")
            return wanted, [msg for _, msg, _ in bag.read_messages(topics=[wanted])]
    except (rosbag.ROSBagException, rosbag.ROSBagFormatException, OSError, ValueError) as error:
        raise InputError(bag_path, f"cannot read the bag: {error}") from None


def trace_steps(messages: list, bag_path: str = "<bag>", topic: str = "") -> list[TraceStep]:
    """The messages as ``TraceStep`` values, timed from the first; a message that cannot be read
    is an ``InputError`` naming the bag, the topic and the message's number (from 1)."""
    from ltl_stack.ros.controller_trace import step_of
    from ltl_stack.ros.valuation import MalformedValuation

    numbered = [(i, m) for i, m in enumerate(messages, 1) if m.state_id >= 0]
    start = numbered[0][1].header.stamp.to_sec() if numbered else 0.0
    steps = []
    for number, msg in numbered:
        try:
            steps.append(step_of(msg, start))
        except MalformedValuation as err:
            raise InputError(bag_path, f"{topic + ': ' if topic else ''}message {number}: {err}") from None
    return steps


def build_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        "check_run", "Check a recorded run (a rosbag of the executor's ~state) against its spec: "
        "environment assumptions and system guarantees per step, goals reached.",
        exit_codes=(Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT),
        epilog="Exit 0: every assumption and guarantee held; 1: something broke (the report says which "
               "clause at which step); 2: a bad spec, mapping or bag. Record a run with ./tools/demo --bag "
               "FILE or rosbag record /<ns>/controller_executor/state.")
    parser.add_argument("spec", help="the controller's spec (.structuredslugs, .slugsin or .spec)")
    parser.add_argument("mapping", help="its proposition mapping YAML (names the scenario's namespace)")
    parser.add_argument("bag", help="the recorded bag")
    parser.add_argument("--topic", help="the ~state topic in the bag (default: the mapping's executor, or the "
                        "only ltl_stack/ControllerState topic)")
    parser.add_argument("--from-start", action="store_true",
                        help="the recording holds the controller's first state: also check the initial "
                             "conditions (ENV_INIT, SYS_INIT) on it")
    parser.add_json("the report")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(sys.argv[1:] if argv is None else argv)
    return cli.run("check_run", lambda: _check(args))


def _check(args) -> int:
    from ltl_stack.runtime.mapping import load_mapping
    from ltl_stack.runtime.run_check import check_run
    from ltl_stack.spec import load_spec

    spec = load_spec(args.spec)
    namespace = load_mapping(args.mapping).scenario_namespace()
    topic, messages = read_states(args.bag, args.topic, namespace)
    steps = trace_steps(messages, args.bag, topic)
    if not steps:
        raise InputError(args.bag, f"no controller state on {topic}")
    try:
        report = check_run(spec, steps, args.from_start)
    except ValueError as error:
        raise UserError(f"{args.bag}: {error}") from None
    if args.json:
        cli.print_json({"bag": args.bag, "topic": topic, **report.to_dict()})
    else:
        print(f"{args.bag}: {topic}")
        for line in report.lines():
            print(line)
    return Exit.OK if report.ok else Exit.NEGATIVE
