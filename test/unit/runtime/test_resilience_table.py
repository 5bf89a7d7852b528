"""The §4.10.4 comparison (``runtime.resilience.resilience_table``): the stories of Examples 10-12 played in
process under base, recovery, EC and recovery + EC, and the comparison with the thesis' figures."""
from __future__ import annotations

import json

import pytest

from ltl_stack.errors import Exit
from ltl_stack.runtime.resilience.resilience_table import (
    EXAMPLES,
    Run,
    main,
    play,
    run_example,
    table,
    verdict,
)
from ltl_stack.runtime.resilience.story import parse_story
from ltl_stack.spec import parse_structured


def by_approach(name: str) -> dict[str, Run]:
    return {r.approach: r for r in run_example(name)}


@pytest.fixture(scope="module")
def alice():
    return by_approach("alice")


@pytest.fixture(scope="module")
def patrol():
    return by_approach("patrol_recycling")


def test_alice_base_fails_at_the_broken_door(alice):
    run = alice["base"]
    assert not run.complete and run.failed_at is not None and run.resyntheses == 0
    assert any("stopped by the violation" in line for line in run.narrative)


def test_alice_recovery_only_needs_no_resynthesis_and_waits_at_the_closed_door(alice):
    run = alice["recovery"]
    assert run.complete and run.resyntheses == 0 and run.recovery_steps > 0
    assert len(run.episodes) == 2 and run.episodes[1] > 140, "waits in road while the door is closed"
    assert run.violated_transitions == sum(run.episodes)


def test_alice_ec_only_resynthesizes_until_unrealizable_then_the_user_helps(alice):
    """§4.10.1.1: EC1 first, EC2 once EC1 is unrealizable, then unrealizable with the closed door;
    the user's GF(doorOpen | doorBroken) makes it realizable and Alice visits storage."""
    run = alice["ec"]
    assert run.complete and run.unrealizable == 1 and run.user == 1
    assert run.ec1_before_unrealizable >= 1 and run.ec2_before_unrealizable >= 1
    lines = run.narrative
    waiting = next(i for i, line in enumerate(lines) if "normal -> waiting_for_user" in line)
    assert "user: adds the env liveness GF(doorOpen | doorBroken)" in lines[waiting + 1]
    opens = next(i for i, line in enumerate(lines) if "story: the door opens" in line)
    assert waiting < opens and "story: Alice visits storage" in lines[opens + 1]
    assert run.verdict.startswith("differs: ec1_before_unrealizable 1 vs 2")


def test_alice_recovery_and_ec_resynthesizes_only_for_the_lasting_closed_door(alice):
    run = alice["recovery+ec"]
    assert run.complete and run.resyntheses == 1 and run.user == 1 and run.ec1 == run.ec2 == 0
    assert run.threshold == 120


def test_patrol_ec_alone_resynthesizes_more_than_recovery_and_ec(patrol):
    """§4.10.4: with EC alone every violation resynthesizes; with recovery + EC (threshold 150
    transitions) only the lasting spill does — unrealizable, the user's GF !spill, once."""
    ec, both = patrol["ec"], patrol["recovery+ec"]
    assert ec.complete and both.complete
    assert ec.resyntheses > both.resyntheses == 1 and both.user == 1 and both.unrealizable == 1
    assert len(both.episodes) == 3 and both.episodes[1] > 150 and both.episodes[0] == both.episodes[2] == 1
    assert both.verdict == "as in the thesis"
    assert patrol["recovery"].resyntheses == 0 and patrol["recovery"].complete
    assert not patrol["base"].complete


def test_block_cutting_recovery_waits_and_ec_resynthesizes_once():
    runs = by_approach("block_cutting")
    assert runs["recovery"].complete and runs["recovery"].resyntheses == 0
    assert runs["ec"].complete and runs["ec"].resyntheses == 1
    assert not runs["base"].complete
    assert all(r.verdict in ("", "as in the thesis") for r in runs.values())


def test_verdict_names_each_difference():
    run = Run("x", "ec", True, 1, 1, 1, 5, 1, 4, 0, 0, 0, [], 0, None, False, None, None)
    assert verdict(run, {}) == ""
    assert verdict(run, {"complete": True, "resyntheses": 5}) == "as in the thesis"
    assert verdict(run, {"resyntheses": 3, "ec1": 1, "user": 1}) == "differs: resyntheses 5 vs 3, user 0 vs 1"


def test_table_lists_every_run_and_points_to_the_explanation(alice):
    text = table(list(alice.values()))
    assert len(text.splitlines()) == 2 + 4 + 1
    assert "differs: ec1_before_unrealizable" in text and "docs/resilience.md" in text


def test_a_story_that_never_completes_is_not_a_completed_mission():
    spec = parse_structured("[INPUT]\nx\n[OUTPUT]\ny\n[SYS_TRANS]\ny' <-> x'\n", "t.structuredslugs")
    story = parse_story("inputs: {x: false}\nbeats:\n  - name: never\n    when: {outputs: {y: true}}", "s.yaml")
    run = play(spec, story, "recovery", max_ticks=5)
    assert not run.complete and run.ticks == 5 and run.beats_fired == 0


def test_cli_json_and_bad_arguments(capsys):
    assert main(["--example", "block_cutting", "--approach", "recovery", "--json"]) == Exit.OK
    (run,) = json.loads(capsys.readouterr().out)
    assert run["example"] == "block_cutting" and run["complete"] is True and run["narrative"]
    with pytest.raises(SystemExit) as info:
        main(["--example", "nowhere"])
    assert info.value.code == Exit.BAD_INPUT
    assert set(EXAMPLES) == {"block_cutting", "alice", "patrol_recycling"}
