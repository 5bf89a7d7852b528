"""Command lines of the code transfer: ``ros_code_transfer`` and ``mine_channels`` (thin; the work is elsewhere)."""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import yaml

from .choose import prompt_text
from .codebase import load_codebase, mine_programs
from .errors import TransferError
from .profiles import load_profile
from .rewrite import write_atomic
from .transfer import TransferOptions, TransferRefused, transfer_program

EXIT_OK, EXIT_UNRESOLVED, EXIT_BAD_INPUT, EXIT_REFUSED = 0, 1, 2, 3

EPILOG = """exit codes:
  0  the target program was written and everything was resolved
  1  the target program was written; the report lists what could not be resolved
  2  bad input (unknown robot, unreadable or inconsistent file, unreachable master, no answer); nothing written
  3  transfer refused (e.g. differential <-> holonomic velocity commands); nothing written
"""


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


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ros_code_transfer", formatter_class=argparse.RawDescriptionHelpFormatter, epilog=EPILOG,
        description="Transfer a ROS Python program written for one robot to another (thesis chapter 2): "
                    "replace channel names, scale/check velocity commands, retarget joint trajectories.")
    parser.add_argument("source", help="the source robot's Python program")
    parser.add_argument("--from", dest="source_robot", required=True, help="source robot name")
    parser.add_argument("--to", dest="target_robot", required=True, help="target robot name")
    parser.add_argument("--robots", required=True, help="robots folder (see docs/code_transfer.md)")
    parser.add_argument("-o", "--output", required=True, help="where to write the target program")
    parser.add_argument("--codebase", help="channel statistics YAML, or a folder of such files and/or "
                                           "<robot>/ program folders (A.1)")
    parser.add_argument("--live", action="store_true",
                        help="list the channels of the running ROS master (A.2; ROS_MASTER_URI)")
    parser.add_argument("--non-interactive", action="store_true",
                        help="never ask: choose by the documented rules and flag each choice in the report")
    parser.add_argument("--json-report", metavar="FILE", help="also write the report as JSON to FILE")
    parser.add_argument("--json", action="store_true", help="print the report as JSON instead of text")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress on standard error")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    started = time.perf_counter()
    progress = None if args.quiet else (lambda msg: print(f"[transfer] {msg}", file=sys.stderr, flush=True))
    report = None
    try:
        src_path = Path(args.source)
        if Path(args.output).resolve() == src_path.resolve():
            raise TransferError("the output would overwrite the source program; choose another -o", args.output)
        try:
            text = src_path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as err:
            raise TransferError(f"cannot read the program: {getattr(err, 'strerror', None) or err}",
                                args.source) from None
        source = load_profile(args.robots, args.source_robot)
        target = load_profile(args.robots, args.target_robot)
        stats = None
        codebase = args.codebase or target.channels
        if codebase:
            stats = load_codebase(codebase, target.name, progress)
            if stats is None and progress:
                progress(f"no channel statistics for {target.name} in {codebase}")
        live = None
        if args.live:
            from ltl_stack.ros.live_channels import list_live_channels

            live = list_live_channels()
            if progress:
                progress(f"{len(live)} channels on the live master")
        ask = None if args.non_interactive else make_asker()
        options = TransferOptions(stats=stats, live=live, ask=ask, progress=progress)
        result = transfer_program(text, source, target, options, filename=str(src_path))
        report = result.report
        report.output_file = args.output
        report.seconds = time.perf_counter() - started
        write_atomic(args.output, result.text, mode=os.stat(src_path).st_mode & 0o777)
        code = EXIT_UNRESOLVED if report.unresolved else EXIT_OK
    except TransferRefused as err:
        print(f"ros_code_transfer: refused: {err}", file=sys.stderr)
        return EXIT_REFUSED
    except TransferError as err:
        print(f"ros_code_transfer: error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    if args.json_report:
        try:
            write_atomic(args.json_report, report.to_json())
        except TransferError as err:
            print(f"ros_code_transfer: error: {err}", file=sys.stderr)
            return EXIT_BAD_INPUT
    sys.stdout.write(report.to_json() if args.json else report.to_text())
    return code


def mine_main(argv: list[str] | None = None) -> int:
    """``mine_channels DIR --robot NAME``: print (or write) the channel statistics of a codebase."""
    parser = argparse.ArgumentParser(
        prog="mine_channels",
        description="Count the channel names per message type in a folder of ROS Python programs "
                    "(thesis §2.5.1 A.1). Exit codes: 0 done, 2 bad input.")
    parser.add_argument("folder", help="folder of programs written for the robot (searched recursively)")
    parser.add_argument("--robot", required=True, help="robot name the statistics are filed under")
    parser.add_argument("-o", "--output", help="write the statistics YAML here (default: standard output)")
    parser.add_argument("--json", action="store_true", help="print JSON instead of YAML")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress on standard error")
    args = parser.parse_args(argv)
    progress = None if args.quiet else (lambda msg: print(msg, file=sys.stderr))
    try:
        stats = mine_programs(args.folder, args.robot, progress)
        for problem in stats.skipped:
            print(f"mine_channels: skipped {problem}", file=sys.stderr)
        data = stats.to_yaml_data()
        text = json.dumps(data, indent=2) + "\n" if args.json else yaml.safe_dump(data, sort_keys=False)
        if args.output:
            write_atomic(args.output, text)
        else:
            sys.stdout.write(text)
    except TransferError as err:
        print(f"mine_channels: error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    return EXIT_OK
