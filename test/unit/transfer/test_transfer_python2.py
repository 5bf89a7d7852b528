"""Python 2 sources: tabs as Python 2 expands them, print statements, refusals naming the construct."""
from pathlib import Path

import pytest
from helpers import require_shared

from ltl_stack.errors import InputError
from ltl_stack.transfer.channels import find_channels
from ltl_stack.transfer.codebase import parse_stats_file
from ltl_stack.transfer.profiles import load_profile
from ltl_stack.transfer.python2 import expand_indentation, python2_parse_text
from ltl_stack.transfer.source_ast import SourceFile
from ltl_stack.transfer.transfer import transfer_program

PY2 = Path(__file__).resolve().parents[2] / "data" / "transfer" / "py2"


def transfer(text, source="turtlebot", target="jackal"):
    robots = require_shared("robots")
    from ltl_stack.transfer.transfer import TransferOptions
    stats = parse_stats_file(require_shared("codebase", "channel_counts.yaml")).get(target)
    return transfer_program(text, load_profile(robots, source), load_profile(robots, target),
                            TransferOptions(stats=stats), filename="prog")


def test_tabs_are_expanded_to_multiples_of_eight_like_python_2():
    text, shifts = expand_indentation("a\n\tb\n  \tc\n        \td\n")
    assert text.split("\n")[1:4] == [" " * 8 + "b", " " * 8 + "c", " " * 16 + "d"]
    assert shifts[:4] == [0, 7, 5, 7]


def test_a_python_2_program_with_mixed_tabs_transfers_and_keeps_its_own_bytes():
    before = (PY2 / "draw_square_py2").read_text()
    result = transfer(before)
    assert result.report.python == "2"
    changed = [(a, b) for a, b in zip(before.splitlines(), result.text.splitlines(), strict=True) if a != b]
    assert changed == [
        ("        self.cmd_vel = rospy.Publisher('cmd_vel_mux/input/navi', Twist, queue_size=10)",
         "        self.cmd_vel = rospy.Publisher('cmd_vel', Twist, queue_size=10)"),
        ("\tforward.linear.x = 0.2", "\tforward.linear.x = 0.5"),
        ("\tturn.angular.z = 0.5", "\tturn.angular.z = 0.37037")], changed
    assert any("read as Python 2" in n and "Python 2 program" in n for n in result.report.notes)
    assert SourceFile(result.text).python == "2"   # the output reads back, as Python 2


def test_print_statements_and_except_commas_are_read_at_their_own_positions():
    code = "import rospy\nprint 'start', rospy\ntry:\n\tpass\nexcept Exception, e:\n\tprint >>f, e\n" \
           "pub = rospy.Publisher('scan', T)\n"
    parsed, _ = python2_parse_text(code, "prog")
    assert [len(a) for a in parsed.splitlines()] == [len(b.expandtabs(8)) if b.startswith("\t") else len(b)
                                                     for b in code.splitlines()]
    assert [(c.name.value, c.line) for c in find_channels(code)] == [("scan", 7)]


@pytest.mark.parametrize("line, construct", [("x = `y`", "backquotes"), ("if a <> b: pass", "<> operator"),
                                             ("exec 'x = 1'", "exec statement"), ("n = 10L", "number 10L"),
                                             ("mode = 0755", "number 0755")])
def test_other_python_2_syntax_is_refused_in_one_line_naming_it(line, construct):
    with pytest.raises(InputError) as err:
        SourceFile(f"import rospy\n{line}\n", "old.py")
    message = str(err.value)
    assert "old.py:2" in message and construct in message and "\n" not in message, message


def test_python_3_syntax_errors_stay_python_3_errors():
    with pytest.raises(InputError) as err:
        SourceFile("x = (\n", "prog.py")
    assert "not valid Python" in str(err.value) and "Python 2 syntax" not in str(err.value)
