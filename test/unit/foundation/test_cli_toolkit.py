"""The shared CLI toolkit: safe file reading, YAML/JSON checks, output refusal, one exit-code table."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from helpers import REPO_ROOT
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack import cli
from ltl_stack.errors import Exit, InputError, OutputError, UserError
from ltl_stack.inputs import MAX_DEPTH, load_json, load_yaml, parse_json, parse_yaml, read_text


def test_read_text_refuses_binary_and_non_utf8_naming_file_and_line(tmp_path):
    binary = tmp_path / "spec.slugsin"
    binary.write_bytes(b"[INPUT]\nx\n\0\x01")
    with pytest.raises(InputError) as e:
        read_text(binary, "spec")
    assert str(e.value).startswith(f"{binary}:3: not a text spec"), str(e.value)
    latin = tmp_path / "map.yaml"
    latin.write_bytes(b"inputs:\n  caf\xe9: {}\n")
    with pytest.raises(InputError) as e:
        read_text(latin)
    assert f"{latin}:2:" in str(e.value) and "not UTF-8" in str(e.value)
    with pytest.raises(InputError, match="no such file"):
        read_text(tmp_path / "missing")
    with pytest.raises(InputError, match="is a directory"):
        read_text(tmp_path)


def test_read_text_keeps_utf8_and_drops_bom(tmp_path):
    f = tmp_path / "a.txt"
    f.write_bytes("\ufeffcafé\n".encode())
    assert read_text(f) == "café\n"


@pytest.mark.parametrize("key", ["5", "yes", "~", "null", "1.5", "[a, b]"])
def test_yaml_keys_must_be_strings(key):
    with pytest.raises(InputError) as e:
        parse_yaml(f"inputs:\n  ok: 1\n  {key}: 2\n", "m.yaml")
    assert str(e.value).startswith("m.yaml:3: key"), str(e.value)


def test_yaml_quoted_keys_and_ordinary_documents_load():
    assert parse_yaml("'5': 1\n'yes': [a, {b: c}]\n", "f") == {"5": 1, "yes": ["a", {"b": "c"}]}
    assert parse_yaml("", "f") is None


def test_yaml_deep_nesting_aliases_and_long_integers_are_refused():
    deep = "[" * (MAX_DEPTH + 5) + "]" * (MAX_DEPTH + 5)
    with pytest.raises(InputError, match="nested more than"):
        parse_yaml(deep, "d.yaml")
    laughs = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [" + ", ".join([f"*{chr(97 + i)}"] * 9) + "]\n" for i in range(8))
    assert parse_yaml(laughs, "ok.yaml")  # 72 aliases: fine, and shared, not copied
    many = "a: &a 1\nb: [" + ", ".join(["*a"] * 2000) + "]\n"
    with pytest.raises(InputError, match="aliases"):
        parse_yaml(many, "many.yaml")
    with pytest.raises(InputError, match="digits"):
        parse_yaml("n: " + "9" * 5000 + "\n", "n.yaml")


def test_yaml_syntax_error_names_the_line():
    with pytest.raises(InputError) as e:
        parse_yaml("a: 1\nb: [1, 2\nc: 3\n", "bad.yaml")
    assert str(e.value).startswith("bad.yaml:") and "invalid YAML" in str(e.value)


def test_json_depth_digits_and_syntax():
    with pytest.raises(InputError, match="nested more than"):
        parse_json("[" * 100_000 + "]" * 100_000, "deep.json")
    assert parse_json('{"a": "[[[[' + "[" * 500 + '"}', "strings.json") == {"a": "[[[[" + "[" * 500}
    with pytest.raises(InputError, match="invalid JSON value"):
        parse_json("[" + "9" * 5000 + "]", "big.json")
    with pytest.raises(InputError) as e:
        parse_json('{\n"a": 1,\n}', "syntax.json")
    # Python 3.13's json names the trailing comma itself (line 2), older ones the next value (line 3)
    assert str(e.value).startswith(("syntax.json:3: invalid JSON", "syntax.json:2: invalid JSON: Illegal trailing comma"))


def test_load_helpers_read_files(tmp_path):
    (tmp_path / "a.yaml").write_text("x: [1, 2]\n")
    (tmp_path / "a.json").write_text(json.dumps({"x": [1, 2]}))
    assert load_yaml(tmp_path / "a.yaml") == load_json(tmp_path / "a.json") == {"x": [1, 2]}


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=200))
def test_any_bytes_give_data_or_one_input_error(raw):
    """Invariant: whatever the bytes, the loaders return data or raise InputError, nothing else."""
    for parse in (parse_yaml, parse_json):
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError:
            continue
        try:
            parse(text, "fuzz")
        except InputError as e:
            assert str(e).startswith("fuzz")


def test_check_outputs_refuses_inputs_links_and_duplicates(tmp_path):
    spec = tmp_path / "spec.slugsin"
    spec.write_text("[INPUT]\n")
    link = tmp_path / "link.slugsin"
    os.symlink(spec, link)
    other = tmp_path / "out.json"
    cli.check_outputs([spec], [other, None])  # fine: a new file
    for out in (spec, link, tmp_path / "." / "spec.slugsin"):
        with pytest.raises(OutputError) as e:
            cli.check_outputs([str(spec)], [str(out)])
        assert e.value.code == Exit.BAD_INPUT and "overwrite the input" in str(e.value)
    with pytest.raises(OutputError, match="two outputs"):
        cli.check_outputs([spec], [other, tmp_path / "out.json"])
    assert not other.exists()


def test_write_output_failure_is_write_failed_and_leaves_nothing(tmp_path):
    target = tmp_path / "missing_dir" / "out.json"
    with pytest.raises(OutputError) as e:
        cli.write_output(target, "{}")
    assert e.value.code == Exit.WRITE_FAILED
    assert not target.parent.exists()


def test_run_turns_user_errors_into_one_line_and_code(capsys):
    def body():
        raise InputError("f.yaml", "bad thing", 4)

    assert cli.run("tool", body) == Exit.BAD_INPUT
    assert capsys.readouterr().err == "tool: error: f.yaml:4: bad thing\n"
    assert cli.run("tool", lambda: None) == 0
    assert cli.run("tool", lambda: Exit.UNREALIZABLE) == 10

    def limit():
        raise UserError("timed out after 1 s", Exit.LIMIT)

    assert cli.run("tool", limit) == 5


def test_lines_printed_by_many_threads_never_share_a_line(capsys):
    """A tool's threads (ROS callbacks, timers, the main loop) print whole lines: a --json reader
    reads one document per line."""
    import threading

    def talk(n: int) -> None:
        for i in range(300):
            print(json.dumps({"thread": n, "i": i, "pad": "x" * (i % 50)}), flush=i % 2 == 0)

    def body() -> None:
        threads = [threading.Thread(target=talk, args=(n,)) for n in range(6)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()

    assert cli.run("tool", body) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 6 * 300
    seen = [json.loads(line) for line in lines]  # every line is one whole document
    for n in range(6):
        assert [d["i"] for d in seen if d["thread"] == n] == list(range(300))


def test_a_prompt_without_newline_is_shown_on_flush_and_an_unfinished_line_is_kept(capsys):
    def prompt() -> None:
        sys.stdout.write("answer? ")
        sys.stdout.flush()
        assert capsys.readouterr().out == "answer? "  # shown before the tool reads the answer
        print("partial", end="")
        raise UserError("no answer", Exit.BAD_INPUT)

    assert cli.run("tool", prompt) == Exit.BAD_INPUT
    assert capsys.readouterr().out == "partial"


def test_tool_parser_epilog_lists_exit_codes_and_help_exits_zero(capsys):
    parser = cli.ToolParser("tool", "does things", exit_codes=(Exit.OK, Exit.BAD_INPUT, Exit.UNREALIZABLE))
    parser.add_json()
    with pytest.raises(SystemExit) as e:
        parser.parse_args(["--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert "10 the specification is unrealizable" in out and "--json" in out
    with pytest.raises(SystemExit) as e:
        parser.parse_args(["--nosuch"])
    assert e.value.code == Exit.BAD_INPUT


FULL = "/dev/full"  # every write fails with ENOSPC
TOOL = ("import sys\nfrom ltl_stack import cli\n"
        "sys.exit(cli.run('tool', lambda: print('x' * 100 * int(sys.argv[1]))))\n")


@pytest.mark.skipif(not os.path.exists(FULL), reason="no /dev/full here")
@pytest.mark.parametrize("command", [
    [sys.executable, "-c", TOOL, "1"],  # buffered: fails only when flushed at the end
    [sys.executable, "-c", TOOL, "10000"],  # fails while writing
    [sys.executable, "-c", "from ltl_stack import cli; cli.ToolParser('tool', 'd').parse_args(['--help'])"],
    [sys.executable, "-m", "ltl_stack.synthesis.cli", str(REPO_ROOT / "config" / "simple" / "simple.structuredslugs"),
     "--json"],
], ids=["flush", "write", "help", "synthesize"])
def test_stdout_that_cannot_be_written_is_one_error_line_and_exit_4(command):
    with open(FULL, "w") as full:
        done = subprocess.run(command, stdout=full, stderr=subprocess.PIPE, text=True, timeout=300)
    prog = "synthesize" if "synthesis" in " ".join(command) else "tool"
    assert (done.returncode, done.stderr) == (Exit.WRITE_FAILED, f"{prog}: error: cannot write the output: "
                                                                 "No space left on device\n"), done.stderr


def test_a_reader_that_stops_early_is_not_an_error():
    """``tool | head``: the closed pipe ends the tool quietly with 0, whatever was still to write."""
    proc = subprocess.Popen([sys.executable, "-c", TOOL, "100000"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert proc.stdout.read(10) == b"x" * 10
    proc.stdout.close()
    assert proc.wait(timeout=300) == 0
    assert proc.stderr.read() == b""
