"""Python 2 sources: tabs as Python 2 expands them, print statements, refusals naming the construct."""
import ast
import tracemalloc
from pathlib import Path

import pytest
from helpers import require_shared
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.errors import InputError
from ltl_stack.transfer.channels import find_channels
from ltl_stack.transfer.codebase import parse_stats_file
from ltl_stack.transfer.profiles import load_profile
from ltl_stack.transfer.python2 import expand_indentation, python2_parse_text
from ltl_stack.transfer.source_ast import SourceFile
from ltl_stack.transfer.transfer import TransferOptions, transfer_program

PY2 = Path(__file__).resolve().parents[2] / "data" / "transfer" / "py2"


def transfer(text, source="turtlebot", target="jackal"):
    robots = require_shared("robots")
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
    assert len(before.splitlines()) == len(result.text.splitlines())
    changed = [(a, b) for a, b in zip(before.splitlines(), result.text.splitlines()) if a != b]
    assert changed == [
        ("        self.cmd_vel = rospy.Publisher('cmd_vel_mux/input/navi', Twist, queue_size=10)",
         "        self.cmd_vel = rospy.Publisher('cmd_vel', Twist, queue_size=10)"),
        ("\tforward.linear.x = 0.2", "\tforward.linear.x = 0.5"),
        ("\tturn.angular.z = 0.5", "\tturn.angular.z = 0.37037")], changed
    assert any("read as Python 2" in n and "Python 2 program" in n for n in result.report.notes)
    assert SourceFile(result.text).python == "2"   # the output reads back, as Python 2


def test_print_statements_and_except_commas_are_read_at_their_own_positions():
    code = "import rospy\nprint 'start', rospy\ntry:\n\tpass\nexcept Exception, e:\n\tprint >>f, e\n" \
           "pub = rospy.Publisher('scan', T)\nif pub: print 'ok'; print\ntry: pass\nexcept E: print 'no'\n"
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


def python2_width(prefix: str) -> int:
    """Python 2's column after an indentation: a tab moves to the next multiple of 8."""
    column = 0
    for ch in prefix:
        column = (column // 8 + 1) * 8 if ch == "\t" else column + 1
    return column


@given(st.lists(st.text(alphabet=" \t", min_size=1, max_size=12), min_size=2, max_size=5))
def test_every_literal_is_found_at_its_own_bytes_however_the_indentation_mixes(prefixes):
    """Lines indented alike for Python 2 (same width after tabs are expanded to multiples of 8) form one
    block; each line's literal is found at its own bytes, tabs and all."""
    width = python2_width(prefixes[0])
    block = [p for p in prefixes if python2_width(p) == width]
    text = "import rospy\nif 1:\n" + "".join(f"{p}rospy.Publisher('t{i}', T)\n" for i, p in enumerate(block))
    src = SourceFile(text, "mixed.py")
    got = [(c.name.value, c.line) for c in find_channels(text)]
    assert got == [(f"t{i}", i + 3) for i in range(len(block))]
    literals = [n for n in ast.walk(src.tree) if isinstance(getattr(n, "value", None), str)
                and n.value.startswith("t")]
    assert sorted(src.segment(n) for n in literals) == sorted(f"'t{i}'" for i in range(len(block)))


def test_many_print_statements_are_read_in_memory_a_small_multiple_of_the_program():
    # memory is measured (tracemalloc's peak while reading), time is not; the whole token list was ~80x
    text = "import sys\n" + "".join(f"print 'line', {i}\n" for i in range(5000))
    tracemalloc.start()
    try:
        parse_text, _ = python2_parse_text(text, "prints.py")
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert parse_text.count("pass") == 5000, parse_text[:200]
    assert peak <= 20 * len(text), peak / len(text)
