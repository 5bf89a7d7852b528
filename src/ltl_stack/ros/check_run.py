"""``check_run SPEC MAPPING BAG``: check a recorded run (a rosbag of the executor's ``~state``) against
the spec: per step whether the environment assumptions held (which clause broke, when), whether every
system guarantee held, how often each goal was reached (``ltl_stack.runtime.runs.conformance``). No master
is needed: the bag is read from the file.

``open_states`` and ``trace_steps`` are also what ``controller_trace --bag`` replays.
"""
from __future__ import annotations

import contextlib
import io
import logging
import struct
import sys
from collections.abc import Iterable, Iterator
from dataclasses import replace
from pathlib import Path

from ltl_stack import cli
from ltl_stack.errors import Exit, InputError, UserError
from ltl_stack.runtime.runs.trace import TraceStep

STATE_TYPE = "ltl_stack/ControllerState"


#: what rosbag and genpy raise on a corrupt or truncated bag, besides their own exceptions (the
#: chunk and record parsers index, unpack, decompress and decode whatever the file holds)
CORRUPT = (OSError, ValueError, KeyError, IndexError, TypeError, AttributeError, EOFError, OverflowError,
           struct.error, UnicodeError, MemoryError)


@contextlib.contextmanager
def open_states(bag_path: str, topic: str | None = None, namespace: str | None = None) -> Iterator:
    """``with open_states(...) as (topic, messages)``: the ControllerState topic of the bag (``topic``,
    else the executor's of the scenario ``namespace``, else the only ControllerState topic it holds)
    and an iterator over ``(record time, message)``, read from the file as it is consumed (memory
    does not grow with the bag). InputError naming the bag otherwise, and for a bag that turns out to
    be corrupt while it is read: one line, never a traceback. When the bag holds the executor's
    latched ``~initial_state`` from the same burst (same stamp) as the first recorded ``~state``, the
    run begins with it: a recorder that connected during the first burst of ``~state`` (the initial
    state and its settling steps, published at once) missed its start there. A bag begun later keeps
    its first recorded state (the initial state's stamp is older)."""
    import genpy
    import rosbag

    bag_errors = (rosbag.ROSBagException, rosbag.ROSBagFormatException, genpy.DeserializationError, *CORRUPT)
    path = Path(bag_path)
    if not path.is_file():
        raise InputError(bag_path, "no such bag file" if not path.exists() else "not a file")
    try:
        bag = rosbag.Bag(bag_path)
    except bag_errors as error:
        raise InputError(bag_path, f"cannot read the bag: {_why(error)}") from None
    try:
        try:
            topics = bag.get_type_and_topic_info().topics
        except bag_errors as error:
            raise InputError(bag_path, f"cannot read the bag: {_why(error)}") from None
        states = sorted(t for t, info in topics.items()  # the latched first state is not a run of its own
                        if info.msg_type == STATE_TYPE and not t.endswith("/initial_state"))
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

        initial = wanted.rsplit("/", 1)[0] + "/initial_state"

        def messages() -> Iterator:
            quiet = _DecodingNotice()
            logging.getLogger("rosout").addFilter(quiet)  # genpy's line about a string it could not decode
            try:
                start = None
                if initial in topics and topics[initial].msg_type == STATE_TYPE:
                    start = next(_quietly(bag_path, bag.read_messages(topics=[initial])), None)
                for index, (when, msg) in enumerate(_quietly(bag_path, bag.read_messages(topics=[wanted]))):
                    if index == 0 and start is not None and start[1].header.stamp == msg.header.stamp:
                        yield when, start[1]  # the first burst's first state, which the recorder missed
                    yield when, msg
            except bag_errors as error:
                raise InputError(bag_path, f"cannot read the bag (corrupt or truncated): {_why(error)}") from None
            finally:
                logging.getLogger("rosout").removeFilter(quiet)

        yield wanted, messages()
    finally:
        try:
            bag.close()
        except bag_errors:
            pass  # a bag that could not be read may not close cleanly either: the error was reported


def _quietly(bag_path: str, records: Iterator) -> Iterator:
    """``(record time, message)`` of rosbag's records; what rosbag prints on stderr about a corrupt
    message definition becomes the one error line."""
    while True:
        noise = io.StringIO()
        with contextlib.redirect_stderr(noise):
            try:
                _, msg, when = next(records)
            except StopIteration:
                return
        if "invalid message definition" in noise.getvalue():
            raise InputError(bag_path, f"cannot read the bag (corrupt): the bag's definition of {STATE_TYPE} is "
                             "not valid")
        yield when.to_sec(), msg


class _DecodingNotice(logging.Filter):
    """Drops genpy's "Characters replaced when decoding" line: a corrupt string in a bag is read with
    replacement characters (and a proposition name that no longer matches is reported in one line)."""

    def filter(self, record: logging.LogRecord) -> bool:
        return not str(record.msg).startswith("Characters replaced when decoding")


def _why(error: BaseException) -> str:
    """An exception as words: a KeyError's text is only the missing key."""
    if isinstance(error, KeyError):
        return f"a record refers to {error} which the bag does not define"
    return str(error) or type(error).__name__


def trace_steps(records: Iterable, source: str = "the bag", topic: str = "") -> Iterator[TraceStep]:
    """The recorded ``(record time, message)`` pairs as ``TraceStep`` values, timed from the first by
    the record time (a bag's record times never go back, while replayed header stamps may), one at a
    time; a message that cannot be read is an ``InputError`` naming the bag, the topic and the
    message's number (from 1)."""
    from ltl_stack.ros.valuation import step_of

    start = None
    for index, (when, msg) in enumerate(records):
        try:
            if msg.state_id < 0:
                continue
            step = step_of(msg, msg.header.stamp.to_sec())
        except (ValueError, TypeError, AttributeError) as error:  # MalformedValuation among them
            raise InputError(source, f"{topic + ': ' if topic else ''}message {index + 1}: {error}") from None
        start = when if start is None else start
        yield replace(step, time=max(0.0, when - start))


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
    from ltl_stack.runtime.config.mapping import load_mapping
    from ltl_stack.runtime.runs.conformance import check_run
    from ltl_stack.spec import load_spec

    spec = load_spec(args.spec)
    namespace = load_mapping(args.mapping).scenario_namespace()
    with open_states(args.bag, args.topic, namespace) as (topic, messages):
        try:
            report = check_run(spec, trace_steps(messages, args.bag, topic), args.from_start)
        except ValueError as error:
            raise UserError(f"{args.bag}: {error}") from None
    if not report.steps:
        raise InputError(args.bag, f"no controller state on {topic}")
    if args.json:
        cli.print_json({"bag": args.bag, "topic": topic, **report.to_dict()})
    else:
        print(f"{args.bag}: {topic}")
        for line in report.lines():
            print(line)
    return Exit.OK if report.ok else Exit.NEGATIVE
