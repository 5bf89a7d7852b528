"""The vacuity check gives the answers of the first, plain implementation (``vacuity_reference``) and
does not do more fixpoints than it needs.

Differential: every spec of ``../shared/specs`` that solves in seconds (the large generated games
and basicEvasion are compared by ``test/benchmarks/bench_vacuity.py``, which runs both checks) and
hypothesis-generated games, with and without the robot's winning positions.
"""
from __future__ import annotations

import pytest
import vacuity_reference
from helpers import shared_dir
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from random_specs import make_spec, random_spec

from ltl_stack.spec import load_spec
from ltl_stack.synthesis import TimeLimitReached, synthesize
from ltl_stack.synthesis import vacuity as vacuity_module
from ltl_stack.synthesis.options import Deadline
from ltl_stack.synthesis.vacuity import check

#: shared specs left to the benchmark (minutes each with the reference check)
SLOW = ("benchmarks/generated/", "basicEvasion")
SPEC_SUFFIXES = (".slugsin", ".structuredslugs", ".spec", ".ltl")


def shared_spec_files() -> list[str]:
    base = shared_dir()
    if base is None:
        return []
    found = sorted(p for p in (base / "specs").rglob("*") if p.suffix in SPEC_SUFFIXES)
    return [str(p.relative_to(base / "specs")) for p in found if not any(s in str(p) for s in SLOW)]


def assert_same_answers(game, winning=None, cpre_winning=None) -> tuple[bool, bool]:
    new = check(game, winning, cpre_winning=cpre_winning)
    old = vacuity_reference.check(game, winning)
    assert new == old
    return new.assumptions_satisfiable, new.assumptions_satisfiable_alone


def compare(spec) -> tuple[bool, bool]:
    """Without and with the robot's winning positions, and with the solve's ``cpre_winning`` as the
    command passes it (for the ordinary and the cooperative solve)."""
    result = synthesize(spec, strategy=False)
    answers = assert_same_answers(result.game)
    if result.realizable:
        assert_same_answers(result.game, result.solution.winning)
        answers = assert_same_answers(result.game, result.solution.winning, result.solution.cpre_winning)
        full = synthesize(spec)  # the cooperative solve first, as an export does
        assert_same_answers(full.game, full.solution.winning, full.solution.cpre_winning)
    return answers


@pytest.mark.parametrize("name", shared_spec_files())
def test_same_answers_as_the_reference_on_the_shared_specs(name):
    compare(load_spec(shared_dir() / "specs" / name))


def test_the_shared_specs_are_found():
    if shared_dir() is None:
        pytest.skip("../shared is absent")
    assert len(shared_spec_files()) >= 30


def varied_spec(seed: int, drop: frozenset[str]):
    """A seeded random spec with some sections left out (no guarantees, no environment goals, ...)."""
    spec = random_spec(seed, max_inputs=3, max_outputs=3)
    for section in drop:
        spec = spec.with_section(section, [])
    return spec


SECTION_SETS = st.frozensets(st.sampled_from(["env_init", "env_safety", "env_liveness", "sys_init", "sys_safety",
                                              "sys_liveness"]), max_size=3)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 5000), drop=SECTION_SETS)
def test_same_answers_as_the_reference_on_generated_games(seed, drop):
    compare(varied_spec(seed, drop))


def test_the_generated_games_meet_every_answer():
    """The differential is only worth something if the games reach every outcome: assumptions met,
    met only without the robot's safety, and met by no play at all."""
    outcomes = set()
    for seed in range(120):
        outcomes.add(compare(varied_spec(seed, frozenset() if seed % 2 else frozenset({"sys_liveness"}))))
    assert outcomes == {(True, True), (False, True), (False, False)}


MEANINGFUL = make_spec(
    ["req"], ["grant"],
    env_liveness=["req"],
    sys_safety=["| ! req' grant'"],
    sys_liveness=["grant"])


def test_a_meaningful_realizable_spec_costs_at_most_one_fair_state_fixpoint(monkeypatch):
    """The joint question answers "not vacuous" alone: the environment's moves without the robot's
    are not examined (the first check ran both greatest fixpoints on every spec)."""
    calls = []
    real = vacuity_module.fair_states

    def counted(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(vacuity_module, "fair_states", counted)
    result = synthesize(MEANINGFUL, strategy=False)
    assert result.realizable
    counts = vacuity_module.Counts()
    found = check(result.game, result.solution.winning, counts=counts)
    assert found.assumptions_satisfiable and found.warnings == ()
    assert len(calls) == 1 and counts.full_fixpoints <= 1


def test_every_predecessor_goes_through_the_game(monkeypatch):
    """One representation of the moves: the check asks the game for predecessors (a partitioned
    transition relation there serves the check too)."""
    result = synthesize(MEANINGFUL, strategy=False)
    game = result.game
    seen = []
    real = game.pre_exists
    monkeypatch.setattr(game, "pre_exists", lambda *a, **k: seen.append(1) or real(*a, **k))
    counts = vacuity_module.Counts()
    check(game, result.solution.winning, counts=counts)
    assert counts.pres > 0 and len(seen) == counts.pres


NEVER_TOGETHER = make_spec(
    ["done"], ["act"],
    env_safety=["| act ! done'"],
    env_liveness=["& act done"],
    sys_safety=["| ! done' ! act'"],
    sys_liveness=["act"])


def test_a_no_stops_once_the_initial_positions_are_out():
    """The greatest fixpoint's iterates only shrink: once one misses every initial position the
    answer is "no" without running it to the end."""
    result = synthesize(NEVER_TOGETHER, strategy=False)
    assert result.realizable
    counts = vacuity_module.Counts()
    found = check(result.game, result.solution.winning, counts=counts)
    assert not found.assumptions_satisfiable and found.assumptions_satisfiable_alone
    assert counts.fixpoints == 2 and counts.full_fixpoints == 1  # the joint one stopped early


def test_the_check_stops_at_the_deadline():
    result = synthesize(MEANINGFUL, strategy=False)
    result.game.deadline = Deadline(1e-9)
    with pytest.raises(TimeLimitReached):
        check(result.game, result.solution.winning)


def test_a_long_check_reports_progress(monkeypatch):
    monkeypatch.setattr(vacuity_module, "QUIET_FOR", -1.0)
    result = synthesize(NEVER_TOGETHER, strategy=False)
    heard: list[str] = []
    check(result.game, result.solution.winning, progress=heard.append)
    assert heard and all(line.startswith("vacuity check: ") for line in heard)
    heard.clear()
    monkeypatch.setattr(vacuity_module, "QUIET_FOR", 3600.0)
    check(result.game, result.solution.winning, progress=heard.append)
    assert heard == []


NO_ENVIRONMENT_GOAL = make_spec(
    ["req"], ["grant"],
    env_safety=["| ! req req'"],
    sys_safety=["| ! req' grant'"],
    sys_liveness=["| grant ! req"])


def test_the_solves_own_predecessor_spares_the_checks():
    """Without environment goals every winning position with an admissible input is fair: the solve's
    ``cpre_winning`` says so and the check computes no predecessor of its own."""
    result = synthesize(NO_ENVIRONMENT_GOAL, strategy=False)
    assert result.realizable and result.solution.cpre_winning is not None
    counts = vacuity_module.Counts()
    found = check(result.game, result.solution.winning, counts=counts,
                  cpre_winning=result.solution.cpre_winning)
    assert found.assumptions_satisfiable and counts.pres == 0
    without = vacuity_module.Counts()
    assert check(result.game, result.solution.winning, counts=without) == found and without.pres > 0


def test_a_spent_budget_leaves_the_answers_open():
    result = synthesize(MEANINGFUL, strategy=False)
    found = check(result.game, result.solution.winning, budget=-1.0)
    assert not found.complete and found.assumptions_satisfiable is None
    assert found.assumptions_satisfiable_alone is None and found.warnings == ()
    assert check(result.game, result.solution.winning, budget=3600.0).complete


def test_a_no_found_before_the_budget_is_spent_is_kept(monkeypatch):
    """The joint answer comes first: a "no" found before the budget runs out still warns."""
    result = synthesize(NEVER_TOGETHER, strategy=False)
    real = vacuity_module.fair_states

    def second_spent(game, sys_trans, within, initial=None, **kwargs):
        if kwargs["counts"].fixpoints:  # the environment's moves alone: past the budget
            raise vacuity_module.OverBudget
        return real(game, sys_trans, within, initial, **kwargs)

    monkeypatch.setattr(vacuity_module, "fair_states", second_spent)
    found = check(result.game, result.solution.winning, budget=3600.0)
    assert not found.complete and found.assumptions_satisfiable is False
    assert found.assumptions_satisfiable_alone is None
    assert len(found.warnings) == 1 and "robot's requirements" in found.warnings[0]
