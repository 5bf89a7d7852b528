"""Thesis Table 2.5, reproduced: the seven example transfers of chapter 2, ours next to the thesis' figures.

    python -m ltl_stack.transfer.thesis_table [--robots DIR] [--codebase FILE] [--json]

Every row runs ``ros_code_transfer`` (its ``main``, in this process) on an example program of
``test/data/transfer`` with the robot profiles shipped in the package (or ``--robots``), the A.1 statistics, the A.2 listing saved from the target's master
(``--topics``) and the user's answers of the thesis given as ``--choose``, and reads the report's
Table 2.5 row. The figures of the thesis are those printed in its Table 2.5.
"""
from __future__ import annotations

import contextlib
import io
import json
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from ltl_stack.cli import ToolParser, print_json, run
from ltl_stack.errors import Exit

from .cli import main as transfer_main
from .errors import TransferError
from .profiles import SHIPPED_ROBOTS

PROG = "thesis_table"
REPO = Path(__file__).resolve().parents[3]


@dataclass(frozen=True)
class Row:
    """One line of Table 2.5: what to run and what the thesis reports for it."""

    label: str
    program: str
    source: str
    target: str
    codebase: str                 # 'robot' (the target profile's channels, or --codebase) or a file in DATA
    topics: str | None            # A.2 listing in DATA/topics, or None
    choose: tuple[str, ...]       # the user's answers (--choose KEY=N)
    thesis: tuple                 # time s, channels, parameters, total, user inputs, examples, lines, errors
    why: str                      # where our counts differ from the thesis' and why


ROWS = (
    Row("Example 1: Keyboard control (Jackal → Turtlebot)", "keyboard_jackal.py", "jackal", "turtlebot",
        "robot", None, (), (2.9, 1, 8, 9, 0, 67, 75, 0),
        "our program (70 lines) was written from the thesis' snippet; parameters: we count the literals "
        "changed (4 non-zero commands); the thesis' 8 is consistent with "
        "counting both fields (linear.x and angular.z) of each of the 4 Twists — the zero fields are "
        "checked and left as they are"),
    Row("Example 2: Obstacle avoidance (Turtlebot → Jackal)", "wander_turtlebot.py", "turtlebot", "jackal",
        "robot", "jackal.yaml", (), (1.4, 2, 4, 6, 0, 12, 85, 0),
        "our program (42 lines) is shorter than the original and has 2 command literals (vel=.3 and the "
        "turn); the thesis does not list its 4"),
    Row("Example 3: Joint trajectory following (UR5 → Jaco 7 DoF)", "follow_trajectory_ur5.py", "ur5",
        "j2s7s300", "thesis_script_counts.yaml", "j2s7s300.yaml", ("FollowJointTrajectoryAction=2",),
        (11.7, 1, 40, 41, 1, 60, 89, 0),
        "parameters: we count list literals (the joint names, 3 position lists, 3 zero velocity lists "
        "resized to 7 joints); the thesis does not say how it counts — single values would give numbers "
        "of its size (7 names + 3 x 7 positions = 28, plus velocities)"),
    Row("Example 4: Greet (Pepper → NAO)", "greet_pepper.py", "pepper", "nao", "thesis_script_counts.yaml",
        "nao.yaml", ("JointTrajectoryAction=2",), (3.3, 2, 14, 16, 1, 0, 209, 0),
        "our program is shorter (no speech, fewer buttons); parameters: 4 Twist literals, 4 position "
        "lists and 2 joint-velocity lists changed (the joint names are the same on both robots)"),
    Row("Example 5: Path planning with MoveIt! (Fetch → PR2)", "moveit_fetch.py", "fetch", "pr2",
        "thesis_script_counts.yaml", None, ("arm_with_torso=2",), (2.8, 2, 0, 2, 1, 110, 69, 0),
        "our program is shorter; the same two replacements (group and pose frame), one answer (A.3)"),
    Row("Example 6: Localization (unknown → Turtlebot)", "localization.py", "unknown", "turtlebot", "robot",
        "turtlebot.yaml", ("Imu=1",), (10.08, 5, 0, 5, 1, 67, 339, 0),
        "our program is a smaller localizer (the thesis used a graph-SLAM node) with the same 5 channels "
        "taken from the robot"),
    Row("Example 6: Localization (unknown → Jackal)", "localization.py", "unknown", "jackal", "robot",
        "jackal.yaml", ("Odometry=2",), (8.74, 5, 0, 5, 1, 12, 339, 0),
        "as for the Turtlebot"),
)
COLUMNS = ("time taken (s)", "channels", "parameters", "total", "user inputs", "target robot examples",
           "lines/errors (thesis) / lines/unresolved (ours)")


def run_row(row: Row, data: Path, robots: Path, robot_codebase: Path | None, out_dir: Path) -> dict:
    """Run one example through ``ros_code_transfer`` and return its report's Table 2.5 row.

    ``robot_codebase`` replaces the target profile's channel statistics in the rows that use them."""
    codebase = robot_codebase if row.codebase == "robot" else data / "codebase" / row.codebase
    argv = [str(data / row.program), "--from", row.source, "--to", row.target, "--robots", str(robots),
            "-o", str(out_dir / f"{row.target}_{row.program}"), "--json", "-q", "--non-interactive"]
    if codebase is not None:
        argv += ["--codebase", str(codebase)]
    if row.topics:
        argv += ["--topics", str(data / "topics" / row.topics)]
    for answer in row.choose:
        argv += ["--choose", answer]
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = transfer_main(argv)
    if code not in (Exit.OK, Exit.NEGATIVE):
        raise TransferError(f"{row.label}: ros_code_transfer exited {code}: {err.getvalue().strip()}")
    report = json.loads(out.getvalue())
    return {"example": row.label, "command": "ros_code_transfer " + " ".join(argv), "exit_code": int(code),
            "ours": report["summary"], "thesis": dict(zip(("time_s", "channels_replaced", "parameters_replaced",
                                                           "total_replacements", "user_inputs",
                                                           "target_robot_examples", "lines_in_file",
                                                           "replacement_errors"), row.thesis)),
            "why_they_differ": row.why}


def to_markdown(results: list[dict]) -> str:
    """The table, each cell 'thesis / ours' (our time: this process, robot files read, imports done)."""
    lines = ["| example | " + " | ".join(COLUMNS) + " | where ours differs, and why |",
             "| --- " * (len(COLUMNS) + 2) + "|"]
    for r in results:
        t, o = r["thesis"], r["ours"]
        examples = "-" if o["target_robot_examples"] is None else o["target_robot_examples"]
        cells = [f"{t['time_s']} / {o['time_s']:.2f}", f"{t['channels_replaced']} / {o['channels_replaced']}",
                 f"{t['parameters_replaced']} / {o['parameters_replaced']}",
                 f"{t['total_replacements']} / {o['total_replacements']}",
                 f"{t['user_inputs']} / {o['user_inputs']}", f"{t['target_robot_examples']} / {examples}",
                 f"{t['lines_in_file']}/{t['replacement_errors']} / {o['lines_in_file']}/{o['unresolved']}"]
        lines.append(f"| {r['example']} | " + " | ".join(cells) + f" | {r['why_they_differ']} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = ToolParser(PROG, "Reproduce thesis Table 2.5: run the seven example transfers of chapter 2 and "
                              "print each row as 'thesis / ours'.", exit_codes=(Exit.OK, Exit.BAD_INPUT))
    parser.add_argument("--robots", default=str(SHIPPED_ROBOTS),
                        help="robots folder (default: the profiles shipped in the package)")
    parser.add_argument("--codebase", help="A.1 statistics (Tables 2.1, 2.3, 2.4) for the rows of Examples 1, 2 "
                                           "and 6 (default: the target profile's channels)")
    parser.add_argument("--examples", default=str(REPO / "test" / "data" / "transfer"),
                        help="folder of the example programs, listings (topics/) and counts (codebase/)")
    parser.add_argument("--keep", metavar="DIR", help="write the transferred programs into DIR")
    parser.add_json("the rows")
    args = parser.parse_args(argv)

    def body() -> int:
        for path, what in ((args.robots, "robots folder"), (args.examples, "examples folder")):
            if not Path(path).is_dir():
                raise TransferError(f"{what} does not exist", path)
        with contextlib.ExitStack() as stack:
            if args.keep:
                out_dir = Path(args.keep)
                out_dir.mkdir(parents=True, exist_ok=True)
            else:
                out_dir = Path(stack.enter_context(tempfile.TemporaryDirectory()))
            codebase = Path(args.codebase) if args.codebase else None
            results = [run_row(row, Path(args.examples), Path(args.robots), codebase, out_dir)
                       for row in ROWS]
        if args.json:
            print_json(results)
        else:
            sys.stdout.write(to_markdown(results))
        return Exit.OK

    return run(PROG, body)


if __name__ == "__main__":
    sys.exit(main())
