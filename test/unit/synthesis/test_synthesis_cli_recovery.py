"""``synthesize --recovery``: the explicit strategy with recovery transitions (thesis §4.6, Alg. 1
lines 19-25) in every export format, its state counts, the independent model check of the written
files, and saved strategies with and without recovery edges stepped by the executor's
``AutomatonStrategy``."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import recovery_reference

from ltl_stack.errors import Exit
from ltl_stack.runtime.executor.explicit import AutomatonStrategy
from ltl_stack.spec import load_spec
from ltl_stack.synthesis.automaton import Automaton
from ltl_stack.synthesis.cli import main
from ltl_stack.synthesis.errors import AssumptionViolation

ROOT = Path(__file__).resolve().parents[3]
ALICE = ROOT / "config" / "alice" / "alice.structuredslugs"

PROBE = """[INPUT]
person
door

[OUTPUT]
stop

[ENV_INIT]
door

[ENV_TRANS]
door'

[SYS_TRANS]
person' -> stop'
"""


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def alice_exports(tmp_path_factory):
    """Alice (thesis Ex. 11, config/alice) exported with and without recovery, in every format."""
    folder = tmp_path_factory.mktemp("alice")
    files = {k: folder / f"{k}" for k in ("plain.json", "rec.json", "rec_slugs.json", "rec.dot")}
    assert main([str(ALICE), "--strategy-json", str(files["plain.json"]), "--quiet"]) == Exit.OK
    return folder, files


def test_recovery_exports_every_format_and_reports_both_counts(alice_exports, capsys):
    folder, files = alice_exports
    code, out, err = run(capsys, ALICE, "--recovery", "--json", "--strategy-json", files["rec.json"],
                         "--slugs-json", files["rec_slugs.json"], "--dot", files["rec.dot"])
    assert code == Exit.OK, err
    summary = json.loads(out)
    plain = Automaton.load(files["plain.json"])
    automaton = Automaton.load(files["rec.json"])
    assert summary["states"] == len(automaton) > summary["states_without_recovery"] == len(plain)
    assert summary["recovery_edges"] == sum(len(s.recovery) for s in automaton.states) > 0
    assert summary["edges"] == sum(len(s.successors) for s in automaton.states)
    assert automaton.metadata["recovery"] is True
    slugs = Automaton.load(files["rec_slugs.json"], inputs=plain.inputs)
    assert [(s.successors, s.recovery) for s in slugs.states] == \
        [(s.successors, s.recovery) for s in automaton.states]
    assert files["rec.dot"].read_text().count("style=dashed") == summary["recovery_edges"]
    # the text line says both counts
    code, out, _ = run(capsys, ALICE, "--recovery")
    assert code == Exit.OK
    assert f"{len(automaton)} states with recovery transitions, {len(plain)} without" in out, out


def test_written_recovery_automaton_passes_the_independent_model_check(alice_exports, capsys):
    folder, files = alice_exports
    if not files["rec.json"].exists():
        assert main([str(ALICE), "--recovery", "--quiet", "--strategy-json", str(files["rec.json"])]) == Exit.OK
    spec = load_spec(ALICE)
    # W of the spec as synthesize solves it (robotics semantics, cooperative), by the numpy solver
    reference = recovery_reference.build(spec, cooperative=True)
    counts = recovery_reference.model_check(
        spec, Automaton.load(files["rec.json"]), Automaton.load(files["plain.json"]),
        lambda v: bool(reference.winning[reference.index(spec, v)]))
    assert counts["recovery"] > 0


def test_recovery_without_an_output_file_still_reports_the_counts(tmp_path, capsys):
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE)
    code, out, _ = run(capsys, spec, "--recovery", "--json")
    assert code == Exit.OK
    summary = json.loads(out)
    # the plain strategy never sees door=0 (4 states); with recovery some states have door=0, and
    # every state answers all four inputs, the two with door=0 by recovery edges
    assert summary["states_without_recovery"] == 4 < summary["states"], summary
    assert summary["edges"] == 4 * summary["states"] and summary["recovery_edges"] == 2 * summary["states"]


def test_saved_strategies_with_and_without_recovery_edges_run_in_the_executor(tmp_path, capsys):
    spec_file = tmp_path / "probe.structuredslugs"
    spec_file.write_text(PROBE)
    spec = load_spec(spec_file)
    with_rec, without = tmp_path / "rec.json", tmp_path / "plain.json"
    assert run(capsys, spec_file, "--recovery", "--strategy-json", with_rec)[0] == Exit.OK
    assert run(capsys, spec_file, "--strategy-json", without)[0] == Exit.OK
    # the executor's loader checks the file against the spec; recovery edges may break env safety
    recovering = AutomatonStrategy(Automaton.load(with_rec, inputs=spec.inputs), spec)
    plain = AutomatonStrategy(Automaton.load(without, inputs=spec.inputs), spec)
    for strategy in (recovering, plain):
        state = strategy.initial_state({"person": False, "door": True}, {"stop": False})
        state = strategy.step(state, {"person": False, "door": True})
    # a person while the door sensor breaks env safety: the saved recovery edge still stops
    state = recovering.step(recovering.initial_state({"person": False, "door": True}, {"stop": False}),
                            {"person": True, "door": False})
    assert state.outputs == {"stop": True}
    state = recovering.step(state, {"person": False, "door": True})  # back to admissible inputs
    assert state.inputs == {"person": False, "door": True}
    # without recovery edges the saved strategy has no answer: recovery then needs the spec's
    # symbolic strategy (the executor synthesizes it; see docs/resilience.md)
    with pytest.raises(AssumptionViolation) as caught:
        plain.step(plain.initial_state({"person": False, "door": True}, {"stop": False}),
                   {"person": True, "door": False})
    assert [c.line for c in caught.value.clauses] == [12]
