"""The ros_code_transfer and mine_channels command lines: outputs, reports, exit codes."""
import json
from pathlib import Path

import yaml
from helpers import require_shared

from ltl_stack.transfer.cli import EXIT_BAD_INPUT, EXIT_OK, EXIT_REFUSED, EXIT_UNRESOLVED, main, mine_main
from ltl_stack.transfer.codebase import mine_programs

DATA = Path(__file__).resolve().parents[2] / "data" / "transfer"


def args(tmp_path, program="keyboard_jackal.py", source="jackal", target="turtlebot", *extra):
    return [str(DATA / program), "--from", source, "--to", target, "--robots", str(require_shared("robots")),
            "-o", str(tmp_path / "out.py"), "-q", *extra]


def test_keyboard_example_writes_program_and_json_report(tmp_path, capsys):
    codebase = require_shared("codebase", "channel_counts.yaml")
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--codebase", str(codebase),
                     "--non-interactive", "--json-report", str(tmp_path / "r.json")))
    assert code == EXIT_OK, capsys.readouterr()
    assert "'cmd_vel_mux/input/navi'" in (tmp_path / "out.py").read_text()
    report = json.loads((tmp_path / "r.json").read_text())
    assert report["summary"]["channels_replaced"] == 1 and report["summary"]["parameters_replaced"] == 4, report
    assert "Channels (§2.5.1):" in capsys.readouterr().out


def test_no_codebase_and_no_master_keeps_the_name_and_exits_1(tmp_path, capsys):
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--non-interactive", "--json"))
    assert code == EXIT_UNRESOLVED
    report = json.loads(capsys.readouterr().out)
    assert report["unresolved"][0]["what"] == "topic 'cmd_vel'", report["unresolved"]
    assert "pub = rospy.Publisher('cmd_vel'" in (tmp_path / "out.py").read_text()


def test_unknown_robot_is_one_clear_error_and_nothing_is_written(tmp_path, capsys):
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "roomba"))
    err = capsys.readouterr().err
    assert code == EXIT_BAD_INPUT
    assert err.startswith("ros_code_transfer: error: ") and "no robot named 'roomba'" in err, err
    assert "Traceback" not in err and not (tmp_path / "out.py").exists()


def test_refused_transfer_exits_3_without_output(tmp_path, capsys):
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "youbot"))
    assert code == EXIT_REFUSED
    assert "refused" in capsys.readouterr().err
    assert not (tmp_path / "out.py").exists()


def test_bad_program_names_file_and_line(tmp_path, capsys):
    bad = tmp_path / "bad.py"
    bad.write_text("import rospy\npub = rospy.Publisher('cmd_vel', Twist\n")
    code = main([str(bad), "--from", "jackal", "--to", "turtlebot", "--robots", str(require_shared("robots")),
                 "-o", str(tmp_path / "out.py")])
    err = capsys.readouterr().err
    assert code == EXIT_BAD_INPUT and f"{bad}: line " in err, err
    assert not (tmp_path / "out.py").exists()


def test_mine_channels_counts_names_per_type(tmp_path, capsys):
    folder = tmp_path / "turtlebot"
    folder.mkdir()
    for i, topic in enumerate(["cmd_vel_mux/input/navi", "/cmd_vel_mux/input/navi", "cmd_vel"]):
        (folder / f"p{i}.py").write_text(f"import rospy\nfrom geometry_msgs.msg import Twist\n"
                                         f"p = rospy.Publisher('{topic}', Twist)\n")
    (folder / "broken.py").write_text("def (\n")
    stats = mine_programs(folder, "turtlebot")
    assert stats.candidates("geometry_msgs/Twist") == [("cmd_vel_mux/input/navi", 2, 2 / 3),
                                                       ("cmd_vel", 1, 1 / 3)], stats.counts
    assert stats.scripts == 3 and len(stats.skipped) == 1, stats
    out = tmp_path / "stats.yaml"
    assert mine_main([str(folder), "--robot", "turtlebot", "-q", "-o", str(out)]) == 0
    assert yaml.safe_load(out.read_text()) == {"turtlebot": {"scripts": 3, "geometry_msgs/Twist": {
        "cmd_vel_mux/input/navi": 2, "cmd_vel": 1}}}
    # a codebase folder with <robot>/ programs works for the transfer directly
    code = main(args(tmp_path, "keyboard_jackal.py", "jackal", "turtlebot", "--codebase", str(tmp_path)))
    assert code == EXIT_OK, capsys.readouterr()
    assert mine_main([str(tmp_path / "nope"), "--robot", "x"]) == 2


def test_asker_repeats_until_a_valid_number_and_fails_clearly_on_eof():
    import io

    import pytest

    from ltl_stack.transfer.cli import make_asker
    from ltl_stack.transfer.errors import TransferError

    out = io.StringIO()
    ask = make_asker(io.StringIO("x\n7\n2\n"), out)
    assert ask("MoveIt group", "", "arm_with_torso", ["arms_and_torso", "left_arm_and_torso"]) == 1
    assert out.getvalue().startswith("Please select a MoveIt group from the list.\n"
                                     "The original MoveIt group was 'arm_with_torso'. Input Example: 1\n"
                                     "1. arms_and_torso\n2. left_arm_and_torso\n"), out.getvalue()
    assert out.getvalue().count("Please enter a number from 1 to 2.") == 2
    with pytest.raises(TransferError, match="no answer to the question about the topic 'cmd_vel'"):
        make_asker(io.StringIO(""), io.StringIO())("topic", "geometry_msgs/Twist", "cmd_vel", ["/a", "/b"])
