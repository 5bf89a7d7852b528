"""Command lines of the code transfer: ``ros_code_transfer`` and ``mine_channels`` (thin; the work is elsewhere).

Both follow the shared tool conventions (``ltl_stack.cli``): one ``<tool>: error: …`` line and a code
from ``ltl_stack.errors.Exit`` for every user mistake, ``--json`` on stdout, outputs written atomically
only after every check, and never over an input. The live master listing (A.2) is an adapter in
``ltl_stack.ros``; ``scripts/ros_code_transfer`` passes it in as ``list_live``.
"""
from __future__ import annotations

import json
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Callable, List, Tuple

import yaml

from ltl_stack.cli import ToolParser, check_outputs, print_json, run, say, warn, write_output, write_outputs
from ltl_stack.errors import Exit, OutputError
from ltl_stack.inputs import read_text

from .channels import load_listing
from .choose import Asker, prompt_text, short_type
from .codebase import is_python_program, load_codebase, mine_programs
from .errors import TransferError
from .profiles import SHIPPED_ROBOTS, UNKNOWN, RobotProfile, load_profile
from .transfer import TransferOptions, transfer_program

TRANSFER = "ros_code_transfer"
MINE = "mine_channels"
#: a function listing the (name, type) channels of the running master, e.g. ``ros.live_channels``
LiveLister = Callable[[], List[Tuple[str, str]]]


def make_asker(stream_in=None, stream_out=None):
    """Ask on the terminal with the §2.5.1 prompt until a valid number is given."""
    stream_in = stream_in or sys.stdin
    stream_out = stream_out or sys.stderr

    def ask(word: str, msg_type: str, original: str, options: Sequence[str]) -> int:
        print(prompt_text(word, msg_type, original, options), file=stream_out, flush=True)
        while True:
            line = stream_in.readline()
            if not line:
                raise TransferError(f"no answer to the question about the {word} '{original}'", "<stdin>")
            answer = line.strip()
            if answer.isdigit() and 1 <= int(answer) <= len(options):
                return int(answer) - 1
            print(f"Please enter a number from 1 to {len(options)}.", file=stream_out, flush=True)

    return ask


def parse_answers(pairs: Sequence[str]) -> dict[str, int]:
    """``--choose KEY=N`` answers: KEY is the original channel/group name or the message type."""
    answers: dict[str, int] = {}
    for pair in pairs:
        key, sep, number = pair.rpartition("=")
        if not sep or not key or not number.isdigit() or int(number) < 1:
            raise TransferError(f"--choose {pair!r}: expected KEY=N with N a whole number from 1 "
                                "(KEY: original name or message type)")
        answers[key] = int(number)
    return answers


def answering(answers: dict[str, int], fallback: Asker | None, used: set[str], stream_out=None) -> Asker:
    """An asker that answers from ``--choose`` first (showing the prompt and the answer), then asks ``fallback``."""
    def ask(word: str, msg_type: str, original: str, options: Sequence[str]) -> int | None:
        keys = [original, original.lstrip("/"), msg_type, short_type(msg_type)]
        key = next((k for k in keys if k in answers), None)
        if key is None:
            return fallback(word, msg_type, original, options) if fallback else None
        used.add(key)
        number = answers[key]
        if number > len(options):
            raise TransferError(f"--choose {key}={number}: the question about the {word} '{original}' has only "
                                f"{len(options)} options")
        print(prompt_text(word, msg_type, original, options) + f"\n{number}  (--choose {key}={number})",
              file=stream_out or sys.stderr, flush=True)
        return number - 1

    return ask


def build_parser() -> ToolParser:
    parser = ToolParser(
        TRANSFER, "Transfer a ROS Python program written for one robot to another (thesis chapter 2): "
                  "replace channel names, scale/check velocity commands, retarget joint trajectories.",
        exit_codes=(Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT, Exit.NO_ROS, Exit.WRITE_FAILED, Exit.REFUSED),
        epilog="1: the target program was written; the report lists what could not be resolved.\n"
               "Nothing is written on any other non-zero code.")
    parser.add_argument("source", help="the source robot's Python program")
    parser.add_argument("--from", dest="source_robot", required=True,
                        help=f"source robot name; '{UNKNOWN}' when the program was written for no known robot "
                             "(channels are chosen for the target alone, nothing is scaled)")
    parser.add_argument("--to", dest="target_robot", required=True, help="target robot name")
    parser.add_argument("--robots", default=str(SHIPPED_ROBOTS),
                        help="robots folder (see docs/code_transfer.md; default: the profiles shipped in the package, "
                             "limits, drive and channel statistics of the thesis' mobile robots)")
    parser.add_argument("-o", "--output", required=True, help="where to write the target program")
    parser.add_argument("--codebase", help="channel statistics YAML, or a folder of such files and/or "
                                           "<robot>/ program folders (A.1)")
    listing = parser.add_mutually_exclusive_group()
    listing.add_argument("--live", action="store_true",
                         help="list the channels of the running ROS master (A.2; ROS_MASTER_URI)")
    listing.add_argument("--topics", metavar="FILE",
                         help="A.2 from a listing saved from the target's master: YAML 'name: package/Type'")
    parser.add_argument("--choose-by-distribution", action="store_true",
                        help="A.1: ask which name to take from the codebase distribution (ranked, with "
                             "probabilities) instead of taking the most probable one")
    parser.add_argument("--choose", metavar="KEY=N", action="append", default=[],
                        help="answer a question without the prompt: option N for the channel or group whose "
                             "original name or message type is KEY (repeatable)")
    parser.add_argument("--keep-distances", action="store_true",
                        help="open-loop programs: scale all speeds by one factor and the durations by its "
                             "inverse, so distances and angles stay (docs/code_transfer.md)")
    parser.add_argument("--non-interactive", action="store_true",
                        help="never ask: choose by the documented rules (or --choose) and flag each choice")
    parser.add_argument("--json-report", metavar="FILE", help="also write the report as JSON to FILE")
    parser.add_json("the report")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress on standard error")
    return parser


def main(argv: list[str] | None = None, list_live: LiveLister | None = None) -> int:
    """``ros_code_transfer``; ``list_live`` is the A.2 adapter (needed for ``--live``)."""
    args = build_parser().parse_args(argv)
    return run(TRANSFER, lambda: _transfer(args, list_live))


def _profile_files(*profiles: RobotProfile) -> list[str]:
    return [str(path) for p in profiles for path in (p.limits and p.limits.file, p.urdf, p.srdf, p.channels)
            if path]


def _transfer(args, list_live: LiveLister | None) -> int:
    started = time.perf_counter()
    progress = None if args.quiet else (lambda msg: say(TRANSFER, msg))
    outputs = [args.output, args.json_report]
    check_outputs([args.source, args.codebase, args.topics], outputs)   # before anything is read or written
    answers = parse_answers(args.choose)
    text = read_text(args.source, "program")
    source = load_profile(args.robots, args.source_robot, allow_unknown=True)
    target = load_profile(args.robots, args.target_robot)
    check_outputs(_profile_files(source, target), outputs)
    stats = None
    codebase = args.codebase or target.channels
    if codebase:
        stats = load_codebase(codebase, target.name, progress)
        if stats is None and progress:
            progress(f"no channel statistics for {target.name} in {codebase}")
    live = load_listing(args.topics) if args.topics else None
    if args.live:
        if list_live is None:
            raise TransferError("--live needs the ROS adapter: run the ros_code_transfer script")
        live = list_live()
        if progress:
            progress(f"{len(live)} channels on the live master")
    used: set[str] = set()
    ask = None if args.non_interactive else make_asker()
    if answers:
        ask = answering(answers, ask, used)
    options = TransferOptions(stats=stats, live=live, ask=ask, progress=progress,
                              choose_by_distribution=args.choose_by_distribution,
                              keep_distances=args.keep_distances)
    result = transfer_program(text, source, target, options, filename=str(args.source))
    for key in sorted(set(answers) - used):
        warn(TRANSFER, f"--choose {key}={answers[key]}: no question was asked about {key!r}")
    report = result.report
    report.output_file = args.output
    report.seconds = time.perf_counter() - started
    outputs = [(args.output, result.text, "target program")]
    if args.json_report:
        outputs.append((args.json_report, report.to_json(), "JSON report"))
    write_outputs(outputs)   # all or none: a failed report leaves the program (and any old one) as it was
    try:
        os.chmod(args.output, os.stat(args.source).st_mode & 0o777)   # executable if the source was
    except OSError as e:
        raise OutputError(f"{args.output}: cannot set its permissions: {e.strerror or e}", Exit.WRITE_FAILED) from None
    if args.json:
        print_json(json.loads(report.to_json()))
    else:
        sys.stdout.write(report.to_text())
    return Exit.NEGATIVE if report.unresolved else Exit.OK


def mine_main(argv: list[str] | None = None) -> int:
    """``mine_channels DIR --robot NAME``: print (or write) the channel statistics of a codebase."""
    parser = ToolParser(
        MINE, "Count the channel names per message type in a folder of ROS Python programs "
              "(thesis §2.5.1 A.1). Programs that cannot be read or parsed are skipped with a warning.",
        exit_codes=(Exit.OK, Exit.BAD_INPUT, Exit.WRITE_FAILED))
    parser.add_argument("folder", help="folder of programs written for the robot (searched recursively)")
    parser.add_argument("--robot", required=True, help="robot name the statistics are filed under")
    parser.add_argument("-o", "--output", help="write the statistics YAML here (default: standard output)")
    parser.add_json("the statistics (instead of YAML)")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress on standard error")
    args = parser.parse_args(argv)
    return run(MINE, lambda: _mine(args))


def _mine(args) -> int:
    folder = Path(args.folder)
    if folder.is_dir():
        programs = [p for p in folder.rglob("*") if p.is_file() and is_python_program(p)]
        check_outputs(programs, [args.output])
    progress = None if args.quiet else (lambda msg: say(MINE, msg))
    stats = mine_programs(folder, args.robot, progress)
    for problem in stats.skipped:
        warn(MINE, f"skipped {problem}")
    data = stats.to_yaml_data()
    text = yaml.safe_dump(data, sort_keys=False)
    if args.output:
        write_output(args.output, text, "statistics")
    if args.json:
        print_json(data)
    elif not args.output:
        sys.stdout.write(text)
    return Exit.OK
