"""Vacuity is never silent: ``synthesize`` warns about a realizable spec whose assumptions
no play can meet or that has no guarantees; an empty spec file is an error."""
from __future__ import annotations

import json
from pathlib import Path

from ltl_stack.errors import Exit
from ltl_stack.spec import load_spec
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.cli import main
from ltl_stack.synthesis.vacuity import check

REPO = Path(__file__).resolve().parents[3]
ENGLISH = REPO / "test" / "data" / "english"
LTLMOP = REPO / "test" / "data" / "ltlmop"

IMPOSSIBLE = """[INPUT]
i
[OUTPUT]
o
[ENV_TRANS]
!i'
[ENV_LIVENESS]
i
[SYS_TRANS]
o'
"""
ROBOT_MAKES_IT_IMPOSSIBLE = """[INPUT]
done
[OUTPUT]
act
[ENV_TRANS]
!act -> !done'
[ENV_LIVENESS]
act & done
[SYS_TRANS]
done' -> !act'
[SYS_LIVENESS]
act
"""
NO_GUARANTEES = "[INPUT]\na\n[OUTPUT]\nb\n"


def _run(path: Path, capsys) -> tuple[int, dict, str]:
    code = main([str(path), "--json"])
    out = capsys.readouterr()
    return code, json.loads(out.out), out.err


def test_thesis_spec2_as_printed_is_realizable_and_vacuous(capsys):
    code, summary, err = _run(ENGLISH / "thesis_spec2.spec", capsys)
    assert code == Exit.OK and summary["realizable"]
    assert summary["assumptions_satisfiable"] is False
    assert len(summary["vacuity"]) == 1 and "robot's requirements" in summary["vacuity"][0]
    assert err.count("warning: vacuous:") == 1


def test_thesis_spec2_with_the_compiled_reading_meets_its_assumptions(capsys):
    """Line 1 with the past tense reads the completions now, as the thesis' compiled spec does."""
    code, summary, err = _run(ENGLISH / "thesis_spec2_compiled_reading.spec", capsys)
    assert code == Exit.OK and summary["realizable"]
    assert summary["assumptions_satisfiable"] is True and summary["vacuity"] == []
    assert "warning" not in err


def test_assumptions_no_play_meets(tmp_path, capsys):
    path = tmp_path / "impossible.structuredslugs"
    path.write_text(IMPOSSIBLE)
    code, summary, err = _run(path, capsys)
    assert code == Exit.OK and summary["assumptions_satisfiable"] is False
    assert "no play meets the environment's assumptions" in err


def test_assumptions_the_robots_safety_rules_out():
    spec = load_spec_text(ROBOT_MAKES_IT_IMPOSSIBLE)
    result = synthesize(spec, strategy=False)
    assert result.realizable
    vacuity = check(result.game)
    assert vacuity.assumptions_satisfiable_alone and not vacuity.assumptions_satisfiable


def test_a_spec_without_guarantees_is_named(tmp_path, capsys):
    path = tmp_path / "none.structuredslugs"
    path.write_text(NO_GUARANTEES)
    code, summary, err = _run(path, capsys)
    assert code == Exit.OK and any("no guarantees" in w for w in summary["vacuity"])
    assert "warning: vacuous: the spec has no guarantees" in err


def test_a_meaningful_spec_has_no_vacuity_warning(capsys):
    code, summary, err = _run(LTLMOP / "hall.spec", capsys)
    assert code == Exit.OK and summary["vacuity"] == [] and summary["warnings"] == []
    # stderr may carry progress lines (printed once the solve has run a second, as on a busy machine)
    assert [line for line in err.splitlines() if "warning" in line.lower() or "vacuous" in line.lower()] == []


def test_an_empty_spec_file_is_an_error(tmp_path, capsys):
    for name in ("empty.slugsin", "empty.spec", "blank.structuredslugs"):
        path = tmp_path / name
        path.write_text("" if name.startswith("empty") else "\n  \n")
        assert main([str(path)]) == Exit.BAD_INPUT
        err = capsys.readouterr().err
        assert err == f"synthesize: error: {path}: the spec file is empty\n"


def test_an_isolated_region_is_a_warning_line(tmp_path, capsys):
    text = (LTLMOP / "hall.spec").read_text().replace("decompose: True", "decompose: False")
    for regions in LTLMOP.glob("*.regions"):
        (tmp_path / regions.name).write_text(regions.read_text())
    path = tmp_path / "hall.spec"
    path.write_text(text)
    code = main([str(path)])
    err = capsys.readouterr().err
    assert code == Exit.UNREALIZABLE
    assert err.count("touches no other region") == 3 and "region dock touches" in err


def load_spec_text(text: str):
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "s.structuredslugs"
        path.write_text(text)
        return load_spec(path)


def _spec_file(tmp_path: Path) -> Path:
    path = tmp_path / "robot.structuredslugs"
    path.write_text(ROBOT_MAKES_IT_IMPOSSIBLE)
    return path


def test_a_timeout_during_the_check_is_one_line_with_the_verdict(tmp_path, capsys, monkeypatch):
    from ltl_stack.synthesis import vacuity

    real = vacuity.fair_states

    def late(game, *args, **kwargs):
        game.deadline.at = 0.0  # the time limit passes as the check starts
        return real(game, *args, **kwargs)

    monkeypatch.setattr(vacuity, "fair_states", late)
    code = main([str(_spec_file(tmp_path)), "--timeout", "60"])
    out = capsys.readouterr()
    assert code == Exit.LIMIT and out.out == ""
    assert out.err == ("synthesize: error: gave up after 60 s (the time limit, --timeout), in the vacuity check "
                       "after the verdict REALIZABLE\n")


def test_the_memory_cap_during_the_check_is_one_line_with_the_verdict(tmp_path, capsys, monkeypatch):
    from ltl_stack.synthesis import vacuity

    def full(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(vacuity, "fair_states", full)
    code = main([str(_spec_file(tmp_path)), "--max-memory", "1G"])
    err = capsys.readouterr().err
    assert code == Exit.LIMIT and err.count("\n") == 1
    assert "memory cap of 1024 MiB (raise it with --max-memory), in the vacuity check after the verdict" in err


def test_a_check_past_its_budget_says_so_and_keeps_the_verdict(tmp_path, capsys, monkeypatch):
    from ltl_stack.synthesis import vacuity

    monkeypatch.setattr(vacuity, "budget_for", lambda solve_cpu: -1.0)  # spent before it starts
    path = tmp_path / "plain.structuredslugs"
    path.write_text(ROBOT_MAKES_IT_IMPOSSIBLE.replace("[ENV_LIVENESS]\nact & done\n", "[ENV_LIVENESS]\n!done\n"))
    code, summary, err = _run(path, capsys)
    assert code == Exit.OK and summary["realizable"]
    assert summary["vacuity_complete"] is False and summary["assumptions_satisfiable"] is None
    assert summary["vacuity"] == []
    assert err.count("\n") == 1 and err.startswith("synthesize: warning: the vacuity check was not completed")
    assert "run it in full with --full-vacuity-check" in err
    code = main([str(path), "--json", "--full-vacuity-check"])
    summary = json.loads(capsys.readouterr().out)
    assert code == Exit.OK and summary["vacuity_complete"] is True and summary["assumptions_satisfiable"] is True
