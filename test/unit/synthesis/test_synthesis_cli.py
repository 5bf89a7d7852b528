"""The ``synthesize`` command: exit codes, outputs, errors, limits (in-process through ``main``, and the
real script where a hard stop or the process's exit matters)."""
from __future__ import annotations

import json
import os
import random
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import needs_cudd

from ltl_stack.errors import Exit
from ltl_stack.synthesis import automaton as automaton_module
from ltl_stack.synthesis.automaton import Automaton
from ltl_stack.synthesis.cli import main

SCRIPT = Path(__file__).resolve().parents[3] / "scripts" / "synthesize"

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

# realizable with slugs' default init semantics only: positions with o true lose
INIT_ONLY = "[INPUT]\ni\n\n[OUTPUT]\no\n\n[SYS_TRANS]\n! o\n"

# the robot counts to 65535 one step at a time: 65,536 rounds of mu Y, tens of seconds of work
COUNTER = "[OUTPUT]\nx:0...65535\n\n[SYS_INIT]\nx = 0\n\n[SYS_TRANS]\nx' = x + 1 | x' = x\n\n[SYS_LIVENESS]\nx = 65535\n"


def random_cnf(variables: int = 70, clauses: int = 200, seed: int = 7) -> str:
    """A random 3-CNF as env_init: its BDD outgrows a few MiB in every variable order."""
    rng = random.Random(seed)
    lines = ["[INPUT]", *[f"v{k}" for k in range(variables)], "", "[OUTPUT]", "o", "", "[ENV_INIT]"]
    for _ in range(clauses):
        lines.append(" | ".join(("!" if rng.random() < 0.5 else "") + f"v{v}"
                                for v in rng.sample(range(variables), 3)))
    return "\n".join(lines) + "\n"


@pytest.fixture
def spec_file(tmp_path):
    def write(text: str, name: str = "spec.slugsin"):
        path = tmp_path / name
        path.write_text(text)
        return str(path)
    return write


def error_lines(capsys) -> list[str]:
    return capsys.readouterr().err.strip().splitlines()


def test_realizable_writes_every_export_and_names_the_options(spec_file, tmp_path, capsys):
    spec = spec_file(COPY)
    out = {k: str(tmp_path / f"s.{k}") for k in ("json", "slugs", "dot")}
    code = main([spec, "--strategy-json", out["json"], "--slugs-json", out["slugs"], "--dot", out["dot"]])
    text = capsys.readouterr().out
    assert code == 0, text
    assert text.startswith("REALIZABLE") and "robotics init semantics, cooperative strategy" in text, text
    ours = Automaton.load(out["json"])
    slugs = json.loads(open(out["slugs"]).read())
    assert len(ours.states) == len(slugs["nodes"]) > 0, (len(ours.states), len(slugs["nodes"]))
    assert ours.metadata["robotics_semantics"] is True and ours.metadata["cooperative"] is True, ours.metadata
    assert open(out["dot"]).read().startswith("digraph")


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz is not installed")
def test_png(spec_file, tmp_path):
    png = tmp_path / "s.png"
    assert main([spec_file(COPY), "--png", str(png), "--quiet"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_json_is_the_summary_on_stdout(spec_file, tmp_path, capsys):
    out = tmp_path / "never.json"
    code = main([spec_file(LOSING), "--json", "--strategy-json", str(out)])
    summary = json.loads(capsys.readouterr().out)
    assert (code, summary["realizable"], out.exists()) == (Exit.UNREALIZABLE, False, False), (code, summary)
    assert (summary["robotics_semantics"], summary["cooperative"]) == (True, True), summary
    assert summary["options"] == "robotics init semantics, cooperative strategy", summary


def test_json_summary_is_a_hidden_alias_of_json(spec_file, capsys):
    assert main([spec_file(COPY), "--json-summary"]) == 0
    assert json.loads(capsys.readouterr().out)["realizable"] is True
    assert "--json-summary" not in subprocess.run([sys.executable, str(SCRIPT), "--help"], capture_output=True,
                                                  text=True, check=True).stdout


def test_default_is_robotics_semantics_and_flags_say_otherwise(spec_file, capsys):
    spec = spec_file(INIT_ONLY)
    codes = (main([spec, "--quiet"]), main([spec, "--quiet", "--robotics-semantics"]),
             main([spec, "--quiet", "--no-robotics-semantics"]))
    assert codes == (Exit.UNREALIZABLE, Exit.UNREALIZABLE, Exit.OK), codes
    assert main([spec, "--json", "--no-robotics-semantics", "--no-cooperative"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["robotics_semantics"], summary["cooperative"]) == (False, False), summary
    assert summary["options"] == "slugs' default init semantics, non-cooperative strategy", summary


def test_bad_spec_is_one_line_with_location(spec_file, capsys):
    code = main([spec_file("[INPUT]\na\n\n[SYS_TRANS]\n& b\n", "bad.slugsin")])
    err = error_lines(capsys)
    assert code == 2 and len(err) == 1 and err[0].startswith("synthesize: error: "), (code, err)
    assert "bad.slugsin:5:" in err[0], err


def test_missing_file(tmp_path, capsys):
    code = main([str(tmp_path / "absent.slugsin")])
    err = error_lines(capsys)
    assert code == 2 and len(err) == 1 and "absent.slugsin" in err[0], (code, err)


def test_max_states_is_a_limit(spec_file, tmp_path, capsys):
    code = main([spec_file(COPY), "--strategy-json", str(tmp_path / "s.json"), "--max-states", "2"])
    err = error_lines(capsys)
    assert code == Exit.LIMIT and len(err) == 1 and "more than 2 states" in err[0], (code, err)
    assert not (tmp_path / "s.json").exists()


def test_explain_and_counterstrategy(spec_file, tmp_path, capsys):
    out = tmp_path / "counter.json"
    code = main([spec_file(LOSING), "--explain", "--counterstrategy", str(out), "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert (code, summary["realizable"], "explanation" in summary) == (10, False, True), summary
    assert json.loads(out.read_text()), out.read_text()


@pytest.mark.parametrize("flag", ["--strategy-json", "--slugs-json", "--dot", "--counterstrategy"])
def test_an_output_that_names_the_spec_is_refused_before_any_work(spec_file, tmp_path, capsys, flag):
    spec = spec_file(COPY)
    link = tmp_path / "link.slugsin"
    link.symlink_to(spec)
    other = tmp_path / "other.dot"
    for target in (spec, str(link)):
        code = main([spec, flag, target, "--dot" if flag != "--dot" else "--slugs-json", str(other)])
        err = error_lines(capsys)
        assert code == 2 and len(err) == 1 and "would overwrite the input" in err[0], (code, err)
        assert Path(spec).read_text() == COPY and not other.exists()


def test_two_outputs_naming_one_file_are_refused(spec_file, tmp_path, capsys):
    out = str(tmp_path / "same")
    assert main([spec_file(COPY), "--dot", out, "--strategy-json", out]) == 2
    assert "named for two outputs" in error_lines(capsys)[0]
    assert not Path(out).exists()


def test_a_failed_png_leaves_no_other_export(spec_file, tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(automaton_module.shutil, "which", lambda _program: None)
    out = tmp_path / "s.json"
    code = main([spec_file(COPY), "--strategy-json", str(out), "--png", str(tmp_path / "s.png")])
    err = error_lines(capsys)
    assert code == Exit.WRITE_FAILED and len(err) == 1 and "Graphviz" in err[0], (code, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.slugsin"], list(tmp_path.iterdir())


def test_an_unwritable_export_leaves_no_other_export(spec_file, tmp_path, capsys):
    out = tmp_path / "s.json"
    code = main([spec_file(COPY), "--strategy-json", str(out), "--dot", str(tmp_path / "absent" / "s.dot")])
    err = error_lines(capsys)
    assert code == Exit.WRITE_FAILED and len(err) == 1 and "s.dot" in err[0], (code, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.slugsin"], list(tmp_path.iterdir())


@needs_cudd
def test_the_memory_cap_is_a_limit_with_one_line(spec_file, tmp_path, capsys):
    small = main([spec_file(COPY), "--max-memory", "2M", "--quiet"])
    code = main([spec_file(random_cnf(), "cnf.structuredslugs"), "--max-memory", "2M",
                 "--strategy-json", str(tmp_path / "s.json")])
    err = error_lines(capsys)
    assert (small, code) == (Exit.OK, Exit.LIMIT), (small, code, err)
    assert len(err) == 1 and "memory cap of 2 MiB" in err[0] and "--max-memory" in err[0], err
    assert not (tmp_path / "s.json").exists()


@pytest.mark.parametrize("argv, message", [
    (["--max-memory", "lots"], "expected a size"),
    (["--max-memory", "0"], "must be positive"),
    (["--timeout", "nan"], "is not a number"),
    (["--timeout", "0"], "is not a number > 0"),
    (["--max-states", "0"], "is not an integer"),
])
def test_bad_limits_are_usage_errors(spec_file, capsys, argv, message):
    with pytest.raises(SystemExit) as info:
        main([spec_file(COPY), *argv])
    assert info.value.code == 2 and message in capsys.readouterr().err


def test_timeout_ends_long_work_with_the_limit_code(spec_file, tmp_path):
    spec = spec_file(COUNTER, "counter.structuredslugs")
    out = tmp_path / "s.json"
    run = subprocess.run([sys.executable, str(SCRIPT), spec, "--timeout", "0.5", "--strategy-json", str(out)],
                         capture_output=True, text=True, timeout=300, env={**os.environ, "PYTHONWARNINGS": "ignore"})
    err = [line for line in run.stderr.splitlines() if "error" in line]
    assert run.returncode == Exit.LIMIT, (run.returncode, run.stderr)
    assert err == ["synthesize: error: gave up after 0.5 s (the time limit, --timeout)"], run.stderr
    assert "Traceback" not in run.stderr and not out.exists()
