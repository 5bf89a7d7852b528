"""The ``synthesize`` command: exit codes, outputs, errors (run in-process through ``main``)."""
from __future__ import annotations

import json
import shutil

import pytest

from ltl_stack.synthesis.automaton import Automaton
from ltl_stack.synthesis.cli import main

COPY = """[INPUT]
i

[OUTPUT]
o

[SYS_TRANS]
! ^ o' i'

[SYS_LIVENESS]
o

[ENV_LIVENESS]
i
"""

LOSING = """[INPUT]
i

[OUTPUT]
o

[SYS_TRANS]
! ^ o i'
"""


@pytest.fixture
def spec_file(tmp_path):
    def write(text: str, name: str = "spec.slugsin"):
        path = tmp_path / name
        path.write_text(text)
        return str(path)
    return write


def test_realizable_writes_every_export(spec_file, tmp_path, capsys):
    spec = spec_file(COPY)
    out = {k: str(tmp_path / f"s.{k}") for k in ("json", "slugs", "dot")}
    code = main([spec, "--json", out["json"], "--slugs-json", out["slugs"], "--dot", out["dot"]])
    assert code == 0, capsys.readouterr()
    assert capsys.readouterr().out.startswith("REALIZABLE")
    ours = Automaton.load(out["json"])
    slugs = json.loads(open(out["slugs"]).read())
    assert len(ours.states) == len(slugs["nodes"]) > 0, (len(ours.states), len(slugs["nodes"]))
    assert open(out["dot"]).read().startswith("digraph")


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed")
def test_png(spec_file, tmp_path):
    png = tmp_path / "s.png"
    assert main([spec_file(COPY), "--png", str(png), "--quiet"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_unrealizable_exit_code_and_json_summary(spec_file, tmp_path, capsys):
    out = tmp_path / "never.json"
    code = main([spec_file(LOSING), "--json-summary", "--json", str(out)])
    summary = json.loads(capsys.readouterr().out)
    assert (code, summary["realizable"], out.exists()) == (10, False, False), (code, summary)


def test_semantics_flag_changes_the_verdict(spec_file):
    # positions with o true lose: fine for slugs' default init, not for robotics semantics
    spec = spec_file("[INPUT]\ni\n\n[OUTPUT]\no\n\n[SYS_TRANS]\n! o\n")
    assert (main([spec, "--quiet"]), main([spec, "--quiet", "--robotics-semantics"])) == (0, 10)


def test_bad_spec_is_one_line_with_location(spec_file, capsys):
    code = main([spec_file("[INPUT]\na\n\n[SYS_TRANS]\n& b\n", "bad.slugsin")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "bad.slugsin:5:" in err[0], (code, err)


def test_missing_file(tmp_path, capsys):
    code = main([str(tmp_path / "absent.slugsin")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "absent.slugsin" in err[0], (code, err)


def test_max_states(spec_file, tmp_path, capsys):
    code = main([spec_file(COPY), "--json", str(tmp_path / "s.json"), "--max-states", "2"])
    assert code == 3 and "more than 2 states" in capsys.readouterr().err
    assert not (tmp_path / "s.json").exists()


def test_explain_and_counterstrategy(spec_file, tmp_path, capsys):
    out = tmp_path / "counter.json"
    code = main([spec_file(LOSING), "--explain", "--counterstrategy", str(out), "--json-summary"])
    summary = json.loads(capsys.readouterr().out)
    assert (code, summary["realizable"], "explanation" in summary) == (10, False, True), summary
    assert json.loads(out.read_text()), out.read_text()
