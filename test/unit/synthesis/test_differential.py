"""Differential tests: the BDD engine's realizability verdicts against two independent solvers.

- ``reference_solver``: explicit-state Eq. 4.2 written inside the tests (no code shared with the engine);
- ``omega`` (PyPI) with its semantics aligned to slugs' (``reference_omega`` says how).

On 300 seeded random specs (see ``random_specs.random_spec``) and both init semantics there must be
zero disagreements. The split of verdicts is checked too: a generator whose specs are all realizable
(or all unrealizable) would prove nothing. See docs/synthesis_correctness.md for the figures.
"""
from __future__ import annotations

import itertools

import pytest
import reference_solver
from hypothesis import given, settings
from hypothesis import strategies as st
from random_specs import make_spec, random_spec
from reference_omega import has_primed_liveness, omega_is_realizable
from test_differential_reference import CASES

from ltl_stack.spec.formula import Var
from ltl_stack.spec.model import Clause
from ltl_stack.synthesis import is_realizable

SEEDS = range(300)
SEMANTICS = (False, True)


def engine_is_realizable(spec, robotics_semantics: bool) -> bool:
    """The engine's public verdict (``ltl_stack.synthesis.is_realizable``)."""
    return is_realizable(spec, robotics_semantics=robotics_semantics)


@pytest.fixture(scope="module")
def reference_verdicts() -> dict[tuple[int, bool], bool]:
    verdicts = {}
    for seed in SEEDS:
        game = reference_solver.build_game(random_spec(seed))
        winning = reference_solver.winning_positions(game)
        for robotics in SEMANTICS:
            verdicts[seed, robotics] = reference_solver.realizable_from(game, winning, robotics)
    return verdicts


def test_random_verdicts_are_mixed(reference_verdicts, capsys):
    for robotics in SEMANTICS:
        realizable = sum(reference_verdicts[seed, robotics] for seed in SEEDS)
        with capsys.disabled():  # the split is part of the evidence: show it in every run
            print(f"\n[random specs] robotics_semantics={robotics}: {realizable}/{len(SEEDS)} realizable")
        assert 0.3 * len(SEEDS) <= realizable <= 0.7 * len(SEEDS), (robotics, realizable)
    # the two semantics must differ on some specs, else the init handling is not exercised
    differ = sum(reference_verdicts[s, False] != reference_verdicts[s, True] for s in SEEDS)
    assert differ >= 20, differ


@pytest.mark.parametrize("name, sections, default, robotics", CASES, ids=[c[0] for c in CASES])
def test_engine_on_hand_checked_specs(name, sections, default, robotics):
    spec = make_spec(["i"], ["o"], **sections)
    got = (engine_is_realizable(spec, False), engine_is_realizable(spec, True))
    assert got == (default, robotics), got


def test_engine_agrees_with_reference_on_random_specs(reference_verdicts):
    disagreements = [(seed, robotics, reference_verdicts[seed, robotics])
                     for seed, robotics in itertools.product(SEEDS, SEMANTICS)
                     if engine_is_realizable(random_spec(seed), robotics) != reference_verdicts[seed, robotics]]
    assert disagreements == [], f"(seed, robotics_semantics, reference verdict): {disagreements}"


def test_engine_winning_positions_equal_reference():
    """Stronger than the verdicts: the whole winning set W of Eq. 4.2, position by position, with
    and without the engine's performance techniques."""
    fixpoint = pytest.importorskip("ltl_stack.synthesis.fixpoint")
    from ltl_stack.synthesis.game import Game

    plain = fixpoint.Options(recycle=False, reorder=False, gauss_seidel=False)
    bad = []
    for seed, state_based in itertools.product(range(0, 300, 3), (False, True)):
        # state-based liveness (primes removed) takes the engine's cheaper state-based iterates
        spec = unprime_liveness(random_spec(seed)) if state_based else random_spec(seed)
        expected = reference_solver.winning_positions(reference_solver.build_game(spec))
        for options in (None, plain):
            game = Game(spec)
            winning = fixpoint.solve(game, options=options).winning
            for x, y in itertools.product(range(expected.shape[0]), range(expected.shape[1])):
                values = {name: bool(x >> k & 1) for k, name in enumerate(spec.inputs)}
                values.update({name: bool(y >> k & 1) for k, name in enumerate(spec.outputs)})
                if (game.bdd.let(values, winning) == game.true) != bool(expected[x, y]):
                    bad.append((seed, state_based, options is None, x, y))
    assert bad == [], f"(seed, state-based liveness, default options, x, y) where W differs: {bad[:20]}"


def test_omega_agrees_with_reference_on_random_specs(reference_verdicts):
    """All 300 specs have primed system liveness: omega gets them through auxiliary goal variables."""
    covered = sum(has_primed_liveness(random_spec(seed)) for seed in SEEDS)
    print(f"{covered}/{len(SEEDS)} specs need the auxiliary-variable encoding of primed liveness")
    disagreements = [(seed, robotics, reference_verdicts[seed, robotics])
                     for seed, robotics in itertools.product(SEEDS, SEMANTICS)
                     if omega_is_realizable(random_spec(seed), robotics_semantics=robotics)
                     != reference_verdicts[seed, robotics]]
    assert disagreements == [], f"(seed, robotics_semantics, reference verdict): {disagreements}"


def unprime_liveness(spec):
    """The spec with every primed variable of its liveness clauses replaced by the unprimed one."""
    def strip(formula):
        from ltl_stack.spec import formula as f

        if isinstance(formula, Var):
            return Var(formula.name)
        if isinstance(formula, f.Const):
            return formula
        if isinstance(formula, f.Not):
            return f.Not(strip(formula.arg))
        if isinstance(formula, (f.And, f.Or)):
            return type(formula)(tuple(strip(a) for a in formula.args))
        return type(formula)(strip(formula.left), strip(formula.right))

    for section in ("env_liveness", "sys_liveness"):
        spec = spec.with_section(section, [Clause(strip(c.formula), c.text, c.file, c.line)
                                           for c in spec.section(section)])
    return spec


def test_omega_agrees_without_auxiliary_variables():
    """The subset omega takes as it is: the same specs with state-based (unprimed) liveness."""
    disagreements = []
    for seed in range(0, 300, 2):
        spec = unprime_liveness(random_spec(seed))
        assert not has_primed_liveness(spec)
        for robotics in SEMANTICS:
            expected = reference_solver.is_realizable(spec, robotics_semantics=robotics)
            if omega_is_realizable(spec, robotics_semantics=robotics) != expected:
                disagreements.append((seed, robotics, expected))
            if engine_is_realizable(spec, robotics) != expected:
                disagreements.append(("engine", seed, robotics, expected))
    assert disagreements == [], disagreements


@pytest.mark.parametrize("name, sections, default, robotics", CASES, ids=[c[0] for c in CASES])
def test_omega_on_hand_checked_specs(name, sections, default, robotics):
    spec = make_spec(["i"], ["o"], **sections)
    got = (omega_is_realizable(spec), omega_is_realizable(spec, robotics_semantics=True))
    assert got == (default, robotics), got


# The robot can only win by moving to o=0, where the environment has no admissible input left (it
# would have to set i' and !i'): slugs calls this realizable (the environment breaks its assumptions
# first). A cooperative strategy may prefer other moves, but the verdict must not change.
FORCES_ENV_DEADLOCK = dict(sys_init=["o"], env_safety=["| o i'", "| o ! i'"], sys_liveness=["0"])


@pytest.mark.parametrize("robotics", SEMANTICS)
def test_synthesize_verdict_does_not_depend_on_cooperation_minimal_case(robotics):
    from ltl_stack.synthesis import synthesize

    spec = make_spec(["i"], ["o"], **FORCES_ENV_DEADLOCK)
    assert reference_solver.is_realizable(spec, robotics_semantics=robotics)
    got = {coop: synthesize(spec, robotics_semantics=robotics, cooperative=coop).realizable
           for coop in (False, True)}
    assert got == {False: True, True: True}, got


def test_synthesize_verdict_equals_reference_on_random_specs(reference_verdicts):
    from ltl_stack.synthesis import synthesize

    disagreements = []
    for seed, robotics in itertools.product(range(0, 300, 3), SEMANTICS):
        spec = random_spec(seed)
        for coop in (False, True):
            got = synthesize(spec, robotics_semantics=robotics, cooperative=coop).realizable
            if got != reference_verdicts[seed, robotics]:
                disagreements.append((seed, robotics, coop, reference_verdicts[seed, robotics]))
    assert disagreements == [], f"(seed, robotics_semantics, cooperative, reference verdict): {disagreements}"


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(min_value=300, max_value=10**6), robotics=st.booleans())
def test_engine_agrees_with_reference_beyond_the_fixed_seeds(seed, robotics):
    spec = random_spec(seed)
    expected = reference_solver.is_realizable(spec, robotics_semantics=robotics)
    assert engine_is_realizable(spec, robotics) == expected, (seed, robotics, expected)
