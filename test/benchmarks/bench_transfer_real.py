"""Code transfer on real ROS programs nobody here wrote: a differential check of the report's claims.

    python test/benchmarks/bench_transfer_real.py [PROGRAMS] [--write]

PROGRAMS (default ``$LTL_REAL_PROGRAMS`` or ``../real_programs`` beside the repository) holds public repositories fetched
outside this repository (teleop_twist_keyboard, turtlebot3, fetch_ros/fetch_gazebo, a Python 2 era
TurtleBot tutorial, ros_tutorials/geometry_tutorials, universal_robot, teleop_tools); they are never
copied into the project. Per run (a program and a robot pair) it reports what was rewritten, what is
unresolved, and whether the output compiles (Python 3: ``compile``; a Python 2 input: read back by the
transfer's Python 2 reader, and by ``python2 -m py_compile`` when a python2 is installed).

The peer in the same run is an independent scan: every line that calls a channel API by name
(a regular expression over the text, not the transfer's ``ast`` reader) must be accounted for in
the report — as a channel, a note, or an unresolved item. A line the report does not mention is a
silent claim that it needs nothing, and a report that says "Everything was resolved." while such a
line exists is a wrong "resolved" claim. Goal: zero. ``--write`` puts the table in
docs/benchmarks/transfer.md (section "Real programs").
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
OUT = ROOT / "docs" / "benchmarks" / "transfer.md"
SECTION = "## Real programs"
BASELINE = "3ac2d30"   # the transfer before it read real programs

# (program path under PROGRAMS, source robot, target robot)
RUNS = [
    ("ros-teleop+teleop_twist_keyboard@HEAD/teleop_twist_keyboard.py", "jackal", "turtlebot"),
    ("ros-teleop+teleop_twist_keyboard@HEAD/teleop_twist_keyboard.py", "turtlebot", "jackal"),
    ("ROBOTIS-GIT+turtlebot3@noetic/turtlebot3_teleop/nodes/turtlebot3_teleop_key", "turtlebot", "jackal"),
    ("ROBOTIS-GIT+turtlebot3@noetic/turtlebot3_example/nodes/turtlebot3_obstacle", "turtlebot", "jackal"),
    ("ROBOTIS-GIT+turtlebot3@noetic/turtlebot3_example/nodes/turtlebot3_pointop_key", "turtlebot", "jackal"),
    ("ROBOTIS-GIT+turtlebot3@noetic/turtlebot3_example/nodes/turtlebot3_server", "turtlebot", "jackal"),
    ("ROBOTIS-GIT+turtlebot3@noetic/turtlebot3_example/nodes/turtlebot3_bumper", "turtlebot", "jackal"),
    ("markwsilliman+turtlebot@master/goforward.py", "turtlebot", "jackal"),
    ("markwsilliman+turtlebot@master/draw_a_square.py", "turtlebot", "jackal"),
    ("markwsilliman+turtlebot@master/goforward_and_avoid_obstacle.py", "turtlebot", "jackal"),
    ("markwsilliman+turtlebot@master/go_to_specific_point_on_map.py", "turtlebot", "jackal"),
    ("markwsilliman+turtlebot@master/kobuki_buttons.py", "turtlebot", "jackal"),
    ("ros+geometry_tutorials@kinetic-devel/turtle_tf/nodes/turtle_tf_listener.py", "turtlebot", "jackal"),
    ("ros+ros_tutorials@noetic-devel/rospy_tutorials/001_talker_listener/talker.py", "turtlebot", "jackal"),
    ("ros-teleop+teleop_tools@noetic-devel/key_teleop/scripts/key_teleop.py", "jackal", "turtlebot"),
    ("ros-teleop+teleop_tools@noetic-devel/mouse_teleop/scripts/mouse_teleop.py", "jackal", "turtlebot"),
    ("fetchrobotics+fetch_gazebo@gazebo9/fetch_gazebo_demo/scripts/demo.py", "fetch", "pr2"),
    ("fetchrobotics+fetch_gazebo@gazebo9/fetch_gazebo_demo/scripts/pick_place_demo.py", "fetch", "pr2"),
    ("fetchrobotics+fetch_gazebo@gazebo9/fetch_gazebo/scripts/prepare_simulated_robot.py", "fetch", "pr2"),
    ("fetchrobotics+fetch_ros@melodic-devel/fetch_teleop/scripts/tuck_arm.py", "fetch", "pr2"),
    ("ros-industrial+universal_robot@indigo-devel/ur_driver/test_move.py", "ur5", "j2n6s300"),
    ("ros-industrial+universal_robot@indigo-devel/ur_driver/test_move.py", "ur5", "j2s7s300"),
    ("ros-industrial+universal_robot@indigo-devel/ur_driver/test_move.py", "ur5", "pr2"),
]

#: the independent peer: calls of channel APIs by name, one per line (not comments)
API_CALL = re.compile(r"\b(Publisher|Subscriber|wait_for_message|ServiceProxy|Service|wait_for_service|"
                      r"SimpleActionClient|SimpleActionServer|MoveGroupInterface|MoveGroupCommander|"
                      r"PickPlaceInterface|PlanningSceneInterface|lookupTransform|lookup_transform|"
                      r"waitForTransform|moveToJointPosition|create_publisher|create_subscription)\s*\(")


def api_lines(text: str) -> list[int]:
    lines = []
    for i, line in enumerate(text.splitlines(), 1):
        code = line.split("#", 1)[0]
        if API_CALL.search(code) and not re.match(r"\s*(def|class)\s", code):
            lines.append(i)
    return lines


def compiles(text: str, python: str, name: str) -> str:
    if python == "3":
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")   # the programs' own SyntaxWarnings are not ours
                compile(text, name, "exec")
            return "yes (Python 3)"
        except SyntaxError as err:
            return f"NO: line {err.lineno}: {err.msg}"
    from ltl_stack.transfer.source_ast import SourceFile
    SourceFile(text, name)   # raises when the Python 2 reader cannot read it back
    python2 = shutil.which("python2")
    if python2 is not None and subprocess.run([python2, "--version"], capture_output=True, check=False).returncode:
        python2 = None   # a shim without an interpreter behind it
    if python2 is None:
        return "yes (Python 2, read back; no python2 here)"
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
        f.write(text)
    done = subprocess.run([python2, "-m", "py_compile", f.name], capture_output=True, text=True, check=False)
    os.unlink(f.name)
    return "yes (python2 -m py_compile)" if done.returncode == 0 else f"NO (python2): {done.stderr.strip()[-80:]}"


def run(programs: Path, path: str, source: str, target: str) -> dict:
    from ltl_stack.errors import InputError
    from ltl_stack.transfer.codebase import parse_stats_file
    from ltl_stack.transfer.errors import TransferError
    from ltl_stack.transfer.profiles import load_profile
    from ltl_stack.transfer.transfer import TransferOptions, TransferRefused, transfer_program

    file = programs / path
    row = {"program": path.split("@", 1)[0].split("+", 1)[1] + ":" + path.split("/", 1)[1], "pair": f"{source} -> {target}"}
    if not file.is_file():
        return {**row, "outcome": "missing (not fetched)"}
    text = file.read_text(encoding="utf-8", errors="replace")
    stats = parse_stats_file(SHARED / "codebase" / "channel_counts.yaml").get(target)
    robots = SHARED / "robots"
    started = time.perf_counter()
    try:
        result = transfer_program(text, load_profile(robots, source), load_profile(robots, target),
                                  TransferOptions(stats=stats), filename=file.name)
    except TransferRefused as err:
        return {**row, "outcome": f"refused: {str(err)[:90]}", "seconds": time.perf_counter() - started}
    except (InputError, TransferError) as err:
        return {**row, "outcome": f"bad input: {str(err)[:90]}", "seconds": time.perf_counter() - started}
    seconds = time.perf_counter() - started
    report = result.report
    mentioned = {c.line for c in report.channels} | {u.line for u in report.unresolved if u.line} | \
        {int(m.group(1)) for n in report.notes for m in [re.match(r"line (\d+):", n)] if m} | \
        {p.line for p in report.parameters}
    silent = [line for line in api_lines(text) if line not in mentioned]
    everything = "Everything was resolved." in report.to_text()
    rewritten = [f"{c.original}->{c.replacement}" for c in report.channels if c.changed]
    python = getattr(report, "python", "3")   # the baseline peer has no Python 2 reader
    return {**row, "outcome": "written", "python": python, "seconds": seconds,
            "channels": rewritten, "parameters": report.parameters_replaced,
            "unresolved": len(report.unresolved), "silent": silent,
            "wrong_resolved": everything and bool(silent),
            "compiles": compiles(result.text, python, file.name)}


def table(rows: list[dict]) -> str:
    out = ["| program | robots | outcome | channels rewritten | parameters | unresolved | silent API lines | "
           "'Everything was resolved' wrong | output compiles |", "| --- " * 9 + "|"]
    for r in rows:
        if r["outcome"] != "written":
            out.append(f"| {r['program']} | {r['pair']} | {r['outcome']} | | | | | | |")
            continue
        channels = ", ".join(r["channels"][:4]) + (f" (+{len(r['channels']) - 4})" if len(r["channels"]) > 4 else "")
        out.append(f"| {r['program']} | {r['pair']} | written (Python {r['python']}) | {channels or '-'} | "
                   f"{r['parameters']} | {r['unresolved']} | {', '.join(map(str, r['silent'])) or '-'} | "
                   f"{'YES' if r['wrong_resolved'] else 'no'} | {r['compiles']} |")
    return "\n".join(out)


def baseline_rows(programs: Path, commit: str) -> list[dict] | None:
    """The same runs with the transfer package of ``commit`` (``git archive`` into a temporary folder,
    run in a child process): the version before it read real programs, as a second peer."""
    with tempfile.TemporaryDirectory() as folder:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", commit, "src"], capture_output=True, check=False)
        if archive.returncode:
            return None
        subprocess.run(["tar", "-x", "-C", folder], input=archive.stdout, check=True)
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(Path(folder) / "src"), os.environ.get("PYTHONPATH", "")]))
        done = subprocess.run([sys.executable, __file__, str(programs), "--json-rows"], capture_output=True,
                              text=True, env=env, check=False)
        return json.loads(done.stdout) if done.returncode == 0 else None


def main(argv: list[str]) -> int:
    args = [a for a in argv if not a.startswith("--")]
    programs = Path(args[0] if args else os.environ.get("LTL_REAL_PROGRAMS", ROOT.parent / "real_programs"))
    rows = [run(programs, *r) for r in RUNS]
    if "--json-rows" in argv:
        print(json.dumps(rows, default=str))
        return 0
    written = [r for r in rows if r["outcome"] == "written"]
    summary = (f"{len(rows)} runs over {len({r['program'] for r in rows})} programs: {len(written)} written, "
               f"{sum(r['outcome'].startswith('refused') for r in rows)} refused, "
               f"{sum(r['outcome'].startswith('bad input') for r in rows)} bad input, "
               f"{sum(r['outcome'].startswith('missing') for r in rows)} missing; "
               f"{sum(r['compiles'].startswith('yes') for r in written)} outputs compile; "
               f"wrong 'Everything was resolved' claims: {sum(r['wrong_resolved'] for r in written)}; "
               f"API lines the report does not mention: {sum(len(r['silent']) for r in written)}")
    text = table(rows)
    baseline = baseline_rows(programs, BASELINE)
    if baseline is not None:
        old = [r for r in baseline if r["outcome"] == "written"]
        summary += (f"\n\nPeer, the transfer before it read real programs (commit {BASELINE[:7]}), same runs: {len(old)} written, "
                    f"{sum(r['outcome'].startswith('bad input') for r in baseline)} bad input, "
                    f"{sum(r['compiles'].startswith('yes') for r in old)} outputs compile; wrong 'Everything was "
                    f"resolved' claims: {sum(r['wrong_resolved'] for r in old)}; API lines its report does not "
                    f"mention: {sum(len(r['silent']) for r in old)}.")
    print(text)
    print(summary)
    if "--write" in argv:
        body = OUT.read_text()
        body = body.split(SECTION)[0].rstrip() + "\n\n" + SECTION + "\n\n" + (
            f"Produced by `python test/benchmarks/bench_transfer_real.py {programs} --write` (non-interactive, "
            "shared codebase statistics, no live master). Programs: public repositories fetched outside the "
            "project, never copied into it. *silent API lines*: lines that call a channel API by name (an "
            "independent regular-expression scan, the peer) which the report neither lists as a channel, a "
            "parameter or a note nor as unresolved.\n\n" + text + "\n\n" + summary + "\n")
        OUT.write_text(body)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
