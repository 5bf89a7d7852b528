"""The ros_code_transfer and mine_channels command lines: outputs, reports, exit codes, bad input."""
import io
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from helpers import REPO_ROOT, require_shared

from ltl_stack.errors import Exit
from ltl_stack.transfer.cli import main, make_asker, mine_main
from ltl_stack.transfer.codebase import mine_programs
from ltl_stack.transfer.errors import TransferError

DATA = Path(__file__).resolve().parents[2] / "data" / "transfer"


def args(tmp_path, program="keyboard_jackal.py", source="jackal", target="turtlebot", *extra):
    return [str(DATA / program), "--from", source, "--to", target, "--robots", str(require_shared("robots")),
            "-o", str(tmp_path / "out.py"), "-q", *extra]


def test_keyboard_example_writes_program_and_json_report(tmp_path, capsys):
    codebase = require_shared("codebase", "channel_counts.yaml")
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--codebase", str(codebase),
                     "--non-interactive", "--json-report", str(tmp_path / "r.json")))
    assert code == Exit.OK, capsys.readouterr()
    assert "'cmd_vel_mux/input/navi'" in (tmp_path / "out.py").read_text()
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["summary"]["channels_replaced"] == 1 and report["summary"]["parameters_replaced"] == 4, report
    assert "Channels (§2.5.1):" in capsys.readouterr().out


def test_no_codebase_and_no_master_keeps_the_name_and_exits_1(tmp_path, capsys):
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--non-interactive", "--json"))
    assert code == Exit.NEGATIVE
    report = json.loads(capsys.readouterr().out)
    assert report["unresolved"][0]["what"] == "topic 'cmd_vel'", report["unresolved"]
    assert "pub = rospy.Publisher('cmd_vel'" in (tmp_path / "out.py").read_text()


def test_unknown_robot_is_one_clear_error_and_nothing_is_written(tmp_path, capsys):
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "roomba"))
    err = capsys.readouterr().err
    assert code == Exit.BAD_INPUT
    assert err.startswith("ros_code_transfer: error: ") and "no robot named 'roomba'" in err, err
    assert "Traceback" not in err and not (tmp_path / "out.py").exists()


def test_refused_transfer_exits_11_without_output(tmp_path, capsys):
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "youbot"))
    err = capsys.readouterr().err
    assert code == Exit.REFUSED == 11
    assert err.startswith("ros_code_transfer: error: ") and "§2.8" in err and err.count("\n") == 1, err
    assert not (tmp_path / "out.py").exists()


def test_live_without_the_adapter_is_a_clear_error(tmp_path, capsys):
    assert main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--live")) == Exit.BAD_INPUT
    assert "--live needs the ROS adapter" in capsys.readouterr().err
    assert not (tmp_path / "out.py").exists()


def test_the_live_listing_is_injected(tmp_path, capsys):
    listing = [("/cmd_vel_mux/input/navi", "geometry_msgs/Twist"), ("/odom", "nav_msgs/Odometry")]
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--live", "--json"),
                list_live=lambda: listing)
    assert code == Exit.OK, capsys.readouterr().err
    channel = json.loads(capsys.readouterr().out)["channels"][0]
    assert (channel["replacement"], channel["method"]) == ("/cmd_vel_mux/input/navi",
                                                           "A.2 live master (the only channel of this type)")


def test_the_cli_module_does_not_import_ros():
    code = ("import sys; import ltl_stack.transfer.cli; "
            "print(sorted(m for m in sys.modules if m.startswith(('ltl_stack.ros', 'rospy', 'rosgraph'))))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(REPO_ROOT / "src")})
    assert done.returncode == 0 and done.stdout.strip() == "[]", (done.stdout, done.stderr)


def test_mine_channels_counts_names_per_type(tmp_path, capsys):
    folder = tmp_path / "turtlebot"
    folder.mkdir()
    for i, topic in enumerate(["cmd_vel_mux/input/navi", "/cmd_vel_mux/input/navi", "cmd_vel"]):
        (folder / f"p{i}.py").write_text(f"import rospy\nfrom geometry_msgs.msg import Twist\n"
                                         f"p = rospy.Publisher('{topic}', Twist)\n")
    (folder / "broken.py").write_text("def (\n")
    (folder / "binary.py").write_bytes(b"import rospy\n\0\n")
    stats = mine_programs(folder, "turtlebot")
    assert stats.candidates("geometry_msgs/Twist") == [("cmd_vel_mux/input/navi", 2, 2 / 3),
                                                       ("cmd_vel", 1, 1 / 3)], stats.counts
    assert stats.scripts == 3 and len(stats.skipped) == 2, stats
    out = tmp_path / "stats.yaml"
    assert mine_main([str(folder), "--robot", "turtlebot", "-q", "-o", str(out)]) == Exit.OK
    err = capsys.readouterr().err
    assert f"mine_channels: warning: skipped {folder / 'binary.py'}:2: not a text program" in err, err
    assert yaml.safe_load(out.read_text()) == {"turtlebot": {"scripts": 3, "geometry_msgs/Twist": {
        "cmd_vel_mux/input/navi": 2, "cmd_vel": 1}}}
    assert mine_main([str(folder), "--robot", "turtlebot", "-q", "--json"]) == Exit.OK
    assert json.loads(capsys.readouterr().out)["turtlebot"]["scripts"] == 3
    # a codebase folder with <robot>/ programs works for the transfer directly
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--codebase", str(tmp_path)))
    assert code == Exit.OK, capsys.readouterr()
    assert mine_main([str(tmp_path / "nope"), "--robot", "x"]) == Exit.BAD_INPUT
    # the statistics must not overwrite one of the programs mined
    before = (folder / "p0.py").read_text()
    assert mine_main([str(folder), "--robot", "turtlebot", "-q", "-o", str(folder / "p0.py")]) == Exit.BAD_INPUT
    assert (folder / "p0.py").read_text() == before


def test_asker_repeats_until_a_valid_number_and_fails_clearly_on_eof():
    out = io.StringIO()
    ask = make_asker(io.StringIO("x\n7\n2\n"), out)
    assert ask("MoveIt group", "", "arm_with_torso", ["arms_and_torso", "left_arm_and_torso"]) == 1
    assert out.getvalue().startswith("Please select a MoveIt group from the list.\n"
                                     "The original MoveIt group was 'arm_with_torso'. Input Example: 1\n"
                                     "1. arms_and_torso\n2. left_arm_and_torso\n"), out.getvalue()
    assert out.getvalue().count("Please enter a number from 1 to 2.") == 2
    with pytest.raises(TransferError, match="no answer to the question about the topic 'cmd_vel'"):
        make_asker(io.StringIO(""), io.StringIO())("topic", "geometry_msgs/Twist", "cmd_vel", ["/a", "/b"])


# ---- bad input: one table, through main(argv) and (a few rows) through the real script ----

def _robots(tmp_path: Path) -> Path:
    """A private copy of the shared robots folder (symlinked files) that a case may break."""
    shared = require_shared("robots")
    robots = tmp_path / "robots"
    for sub in ("limits", "urdf", "srdf"):
        (robots / sub).mkdir(parents=True)
        for f in (shared / sub).iterdir():
            (robots / sub / f.name).symlink_to(f)
    return robots


def _replace(path: Path, data: bytes) -> None:
    path.unlink()
    path.write_bytes(data)


def _program(data: bytes):
    def make(tmp, robots, a):
        (tmp / "prog.py").write_bytes(data)
        a["program"] = tmp / "prog.py"
        return tmp / "prog.py", 0
    return make


def _robot_file(relative: str, data: bytes, program="keyboard_jackal.py", source="jackal", target="turtlebot"):
    def make(tmp, robots, a):
        _replace(robots / relative, data)
        a.update(program=DATA / program, source=source, target=target)
        return robots / relative, 0
    return make


def _codebase(data: bytes):
    def make(tmp, robots, a):
        (tmp / "counts.yaml").write_bytes(data)
        a["extra"] = ["--codebase", str(tmp / "counts.yaml")]
        return tmp / "counts.yaml", 0
    return make


def _profile(data: bytes):
    def make(tmp, robots, a):
        (robots / "turtlebot.yaml").write_bytes(data)
        return robots / "turtlebot.yaml", 0
    return make


def _output_is(which: str):
    def make(tmp, robots, a):
        source = tmp / "keyboard.py"
        shutil.copy(DATA / "keyboard_jackal.py", source)
        a["program"] = source
        if which == "source":
            a["output"] = source
        elif which == "source-symlink":
            (tmp / "link.py").symlink_to(source)
            a["output"] = tmp / "link.py"
        elif which == "report-is-source":
            a["extra"] = ["--json-report", str(source)]
        elif which == "report-is-codebase":
            counts = tmp / "counts.yaml"
            shutil.copy(require_shared("codebase", "channel_counts.yaml"), counts)
            a["extra"] = ["--codebase", str(counts), "--json-report", str(counts)]
            return counts, None
        elif which == "output-is-target-limits":
            a["output"] = robots / "limits" / "turtlebot.yaml"
            return robots / "limits" / "turtlebot.yaml", None
        elif which == "report-is-output":
            a["extra"] = ["--json-report", str(tmp / "out.py")]
            return tmp / "out.py", None
        return source, None
    return make


DEEP_YAML = b"linear: " + b"[" * 120 + b"]" * 120 + b"\n"
LONG_INT = b"linear:\n  x:\n    upper: " + b"9" * 5000 + b"\n"
BAD_CASES = {
    "program with a NUL byte": (_program(b"import rospy\nx = 1\0\n"), "not a text program"),
    "program not UTF-8": (_program(b"import rospy\n# caf\xe9\n"), "not UTF-8"),
    "program not valid Python": (_program(b"import rospy\npub = rospy.Publisher('x', Twist\n"), "not valid Python"),
    "program nested too deeply for the parser": (_program(b"x = " + b"-" * 100000 + b"1\n"), "nested too deeply"),
    "program whose syntax tree is absurdly deep": (_program(b"x = a" + b".b" * 400 + b"\n"), "levels deep"),
    "program indented too deeply": (_program(b"def f():\n" + b"".join(b" " * i + b"if x:\n" for i in range(1, 120))
                                             + b" " * 120 + b"pass\n"), "not valid Python"),
    "limits key not a string": (_robot_file("limits/turtlebot.yaml", b"linear:\n  5: {upper: 1}\n"),
                                "is not a string"),
    "limits key yes:": (_robot_file("limits/turtlebot.yaml", b"linear:\n  x:\n    yes: 1\n"), "is not a string"),
    "limits nested deeply": (_robot_file("limits/turtlebot.yaml", DEEP_YAML), "levels deep"),
    "limits with a long integer": (_robot_file("limits/turtlebot.yaml", LONG_INT), "digits"),
    "limits not UTF-8": (_robot_file("limits/jackal.yaml", b"linear:\n  x: {upper: 1} # \xff\n"), "not UTF-8"),
    "limits binary": (_robot_file("limits/jackal.yaml", b"\0\1\2"), "NUL byte"),
    "profile key not a string": (_profile(b"~: 1\n"), "is not a string"),
    "codebase key not a string": (_codebase(b"turtlebot:\n  geometry_msgs/Twist:\n    5: 3\n"), "is not a string"),
    "codebase long integer": (_codebase(b"turtlebot:\n  scripts: " + b"1" * 4500 + b"\n"), "digits"),
    "codebase invalid YAML": (_codebase(b"turtlebot: [\n"), "invalid YAML"),
    "URDF binary": (_robot_file("urdf/ur5.urdf", b"<robot>\0</robot>", "follow_trajectory_ur5.py", "ur5",
                                "j2n6s300"), "NUL byte"),
    "URDF not UTF-8": (_robot_file("urdf/j2n6s300.urdf", b"<robot name='x'>\n<!-- \xfe -->\n</robot>",
                                   "follow_trajectory_ur5.py", "ur5", "j2n6s300"), "not UTF-8"),
    "URDF malformed XML": (_robot_file("urdf/j2n6s300.urdf", b"<robot name='x'>\n<link name='a'>\n</robot>\n",
                                       "follow_trajectory_ur5.py", "ur5", "j2n6s300"), "not valid XML"),
    "SRDF malformed XML": (_robot_file("srdf/pr2.srdf", b"<robot name='pr2'>\n<group name='a'>\n",
                                       "moveit_fetch.py", "fetch", "pr2"), "not valid XML"),
    "SRDF binary": (_robot_file("srdf/pr2.srdf", b"\0" * 10, "moveit_fetch.py", "fetch", "pr2"), "NUL byte"),
    "output is the source": (_output_is("source"), "would overwrite the input"),
    "output is a symlink to the source": (_output_is("source-symlink"), "would overwrite the input"),
    "JSON report is the source": (_output_is("report-is-source"), "would overwrite the input"),
    "JSON report is the codebase": (_output_is("report-is-codebase"), "would overwrite the input"),
    "output is the target's limits": (_output_is("output-is-target-limits"), "would overwrite the input"),
    "JSON report is the output": (_output_is("report-is-output"), "named for two outputs"),
}
LINE_OF = {"program with a NUL byte": 2, "program not UTF-8": 2, "program not valid Python": 2,
           "limits key not a string": 2, "limits key yes:": 3, "limits with a long integer": 3,
           "profile key not a string": 1, "codebase key not a string": 3, "URDF malformed XML": 3,
           "SRDF malformed XML": 3, "limits not UTF-8": 2, "URDF not UTF-8": 2}


def _prepare(tmp_path, case):
    robots = _robots(tmp_path)
    a = {"program": DATA / "keyboard_jackal.py", "source": "jackal", "target": "turtlebot",
         "output": tmp_path / "out.py", "extra": []}
    named, _ = BAD_CASES[case][0](tmp_path, robots, a)
    argv = [str(a["program"]), "--from", a["source"], "--to", a["target"], "--robots", str(robots),
            "-o", str(a["output"]), "--non-interactive", "-q", *a["extra"]]
    snapshot = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and not p.is_symlink()}
    return argv, named, snapshot


def _check(case, code, err, tmp_path, named, snapshot):
    assert code == Exit.BAD_INPUT, (case, code, err)
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("ros_code_transfer: error: "), (case, err)
    assert str(named) in lines[0] and BAD_CASES[case][1] in lines[0], (case, err)
    if case in LINE_OF:
        assert f"{named}:{LINE_OF[case]}: " in lines[0], (case, err)
    assert "Traceback" not in err
    after = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and not p.is_symlink()}
    assert after == snapshot, f"{case}: files were created or changed"


@pytest.mark.parametrize("case", list(BAD_CASES))
def test_bad_input_is_one_error_naming_the_file_and_nothing_is_written(tmp_path, capsys, case):
    argv, named, snapshot = _prepare(tmp_path, case)
    code = main(argv)
    _check(case, code, capsys.readouterr().err, tmp_path, named, snapshot)


@pytest.mark.parametrize("case", ["program with a NUL byte", "output is a symlink to the source",
                                  "limits key not a string", "URDF malformed XML"])
def test_bad_input_through_the_real_script(tmp_path, case):
    argv, named, snapshot = _prepare(tmp_path, case)
    env = {k: v for k, v in os.environ.items() if k != "ROS_MASTER_URI"}
    env["PYTHONPATH"] = os.pathsep.join([str(REPO_ROOT / "src"), env.get("PYTHONPATH", "")])
    done = subprocess.run([sys.executable, str(REPO_ROOT / "scripts" / "ros_code_transfer"), *argv],
                          capture_output=True, text=True, timeout=300, env=env)
    _check(case, done.returncode, done.stderr, tmp_path, named, snapshot)
    assert done.stdout == ""


def test_a_failed_report_write_leaves_no_program(tmp_path, capsys):
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--non-interactive",
                     "--json-report", str(tmp_path / "no" / "such" / "dir" / "r.json")))
    err = capsys.readouterr().err
    assert code == Exit.WRITE_FAILED and "cannot write the JSON report" in err, err
    assert not (tmp_path / "out.py").exists()
    # an older program at -o stays as it was
    (tmp_path / "out.py").write_text("old\n")
    (tmp_path / "report_dir").mkdir()
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--non-interactive",
                     "--json-report", str(tmp_path / "report_dir")))
    assert code == Exit.BAD_INPUT, capsys.readouterr().err  # a folder is refused before any work
    assert (tmp_path / "out.py").read_text() == "old\n" and list((tmp_path / "report_dir").iterdir()) == []


def test_the_target_program_keeps_the_source_mode(tmp_path, capsys):
    source = tmp_path / "kb.py"
    source.write_bytes((DATA / "keyboard_jackal.py").read_bytes())
    source.chmod(0o750)
    argv = args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--non-interactive")
    argv[0] = str(source)
    assert main(argv) == Exit.NEGATIVE, capsys.readouterr().err
    assert (tmp_path / "out.py").stat().st_mode & 0o777 == 0o750


def test_mine_channels_through_the_real_script_refuses_output_over_a_program(tmp_path):
    folder = tmp_path / "bot"
    folder.mkdir()
    (folder / "a.py").write_text("import rospy\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO_ROOT / "src"), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, str(REPO_ROOT / "scripts" / "mine_channels"), str(folder), "--robot",
                           "bot", "-o", str(folder / "a.py")], capture_output=True, text=True, timeout=300, env=env)
    assert done.returncode == Exit.BAD_INPUT and done.stderr.startswith("mine_channels: error: "), done.stderr
    assert (folder / "a.py").read_text() == "import rospy\n"


def test_the_command_line_starts_without_numpy_scipy_or_yourdfpy():
    """Their imports cost ~0.6 s per call; only a program with joint commands needs them (retarget)."""
    code = ("import sys, ltl_stack.transfer.cli\n"
            "print(sorted(m for m in ('numpy', 'scipy', 'yourdfpy') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stdout.strip() == "[]", done.stdout + done.stderr


def test_keep_distances_option_and_python_2_in_the_json_report(tmp_path, capsys):
    code = main(args(tmp_path, "py2/draw_square_py2", "turtlebot", "jackal", "--keep-distances",
                     "--non-interactive", "--json"))
    report = json.loads(capsys.readouterr().out)
    assert code == Exit.NEGATIVE, report["unresolved"]   # cmd_vel_mux/input/navi: no codebase here
    assert report["python"] == "2"
    out = (tmp_path / "out.py").read_text()
    assert "\tr = rospy.Rate(3.703704)\n" in out and "\tforward.linear.x = 0.148148\n" in out, out
